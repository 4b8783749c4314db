// The coarse tracker's robust weighting of its warped points (kernels/coarse_warp.h), four at a
// time: per point with residual r and squared reference gradient g2,
//   gradient weight gw = c2 / (c2 + g2) (1 when c2 = 0),
//   inlier when |r| <= cutoff (NaN is an outlier); base outlier when |r| > base_cutoff;
//   an inlier's Huber weight hw = min(1, k / |r|), cost = hw (2 - hw) r^2, weight hw gw;
//   energy term gw cost (inlier) or gw outlier_cost (outlier), Huber term cost or outlier_cost.
// The tracker adds the terms in point order (the sums are not reordered). weighCoarse4<V> is the
// SIMD kernel (V from math/simd/vec4f.h); reference::weighCoarsePoint the per-point formulation
// with the same operations in the same order (no fused multiply-add: -ffp-contract=off), so the
// two give the same bits, which the tests check for every vector type.
#pragma once

#include <cmath>

#include "math/simd/vec4f.h"

namespace ldsm {
namespace simd {

/// What the weighting of one level's evaluation shares.
struct CoarseWeighting {
  float c2 = 0.f;             ///< squared gradient-weight constant (0: no gradient weight)
  float huber = 9.f;          ///< k
  float cutoff = 1e30f;       ///< residuals above it are outliers
  float outlier_cost = 0.f;   ///< the Huber cost charged for an outlier
  float base_cutoff = 1e30f;  ///< residuals above it count as base outliers
};

/// One point's weighting.
struct CoarseWeightedPoint {
  float energy;  ///< gw * (cost or outlier_cost)
  float huber;   ///< cost or outlier_cost
  float weight;  ///< hw * gw (inliers)
  bool inlier;
  bool base_outlier;
};

/// Four points' weightings as rows; bit i of `inlier` / `base_outlier` for point i.
struct alignas(16) CoarseWeights4 {
  float energy[4], huber[4], weight[4];
  int inlier = 0;
  int base_outlier = 0;
};

namespace reference {

inline CoarseWeightedPoint weighCoarsePoint(const CoarseWeighting& p, float r, float grad_sq) {
  CoarseWeightedPoint out;
  const float abs_r = std::abs(r);
  const float gw = p.c2 > 0.f ? p.c2 / (p.c2 + grad_sq) : 1.f;
  out.base_outlier = abs_r > p.base_cutoff;
  out.inlier = abs_r <= p.cutoff;
  if (!out.inlier) {  // also NaN
    out.energy = gw * p.outlier_cost;
    out.huber = p.outlier_cost;
    out.weight = 0.f;
    return out;
  }
  const float hw = abs_r < p.huber ? 1.f : p.huber / abs_r;
  const float cost = hw * (2.f - hw) * r * r;
  out.energy = gw * cost;
  out.huber = cost;
  out.weight = hw * gw;
  return out;
}

}  // namespace reference

/// Weighs the four residuals r[0..3] (squared reference gradients g2[0..3]). Lanes of points
/// that are not inside the frame may hold anything (their bits and values are unspecified).
template <class V>
[[gnu::always_inline]] inline void weighCoarse4(const CoarseWeighting& p, const float* r,
                                                const float* g2, CoarseWeights4& out) {
  const V R = V::loadu(r);
  const V abs_r = absolute(R);
  const V one = V::set1(1.f);
  const V gw = p.c2 > 0.f ? V::set1(p.c2) / (V::set1(p.c2) + V::loadu(g2)) : one;
  const V k = V::set1(p.huber);
  const V cutoff = V::set1(p.cutoff);
  const typename V::Mask inlier = cutoff >= abs_r;  // ordered: NaN is not
  out.inlier = laneBits(inlier);
  out.base_outlier = laneBits(abs_r > V::set1(p.base_cutoff));
  const V hw = select(abs_r < k, one, k / abs_r);
  const V cost = hw * (V::set1(2.f) - hw) * R * R;
  const V outlier_cost = V::set1(p.outlier_cost);
  select(inlier, gw * cost, gw * outlier_cost).store(out.energy);
  select(inlier, cost, outlier_cost).store(out.huber);
  select(inlier, hw * gw, V::zero()).store(out.weight);
}

}  // namespace simd
}  // namespace ldsm
