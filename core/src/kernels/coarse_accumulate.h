// The coarse tracker's normal equations H = sum w J^T J, g = sum w J^T r over its residuals
// (struct of arrays, see frontend/coarse_residuals.h for the residual and the parameter order
// [rho (3), phi (3), a, b]), four residuals per SIMD vector. The Jacobian row is computed in the
// kernel from the stored per-residual values:
//   J = [ dx_fx iz, dy_fy iz, -iz (dx_fx nx + dy_fy ny),
//         -dx_fx nx ny - dy_fy (1 + ny^2), dx_fx (1 + nx^2) + dy_fy nx ny, dy_fy nx - dx_fx ny,
//         -ref_term, -1 ].
// Sums are kept per lane in float over blocks of points and moved into double per block.
#pragma once

#include <algorithm>

#include "math/simd/vec4f.h"

namespace ldsm {
namespace simd {

constexpr int kCoarseRow = 8;
constexpr int kCoarseUpper = kCoarseRow * (kCoarseRow + 1) / 2;  ///< 36
constexpr int kCoarseSums = kCoarseUpper + kCoarseRow;           ///< 44

/// Index of sum w J_i J_j (i <= j) in the sums: the upper triangle, row by row.
constexpr int coarseUpperIndex(int i, int j) {
  return i * kCoarseRow - i * (i - 1) / 2 + (j - i);
}

/// The residuals' arrays (each `count` long).
struct CoarseResidualArrays {
  const float* dx_fx = nullptr;
  const float* dy_fy = nullptr;
  const float* nx = nullptr;
  const float* ny = nullptr;
  const float* iz = nullptr;
  const float* ref_term = nullptr;
  const float* residual = nullptr;
  const float* weight = nullptr;
  int count = 0;
};

namespace detail {

/// Adds four residuals (lanes) to the float lane sums.
template <class V>
inline void coarseAccumulate4(V dxf, V dyf, V nx, V ny, V iz, V ref, V r, V w, V* acc) {
  const V one = V::set1(1.f);
  const V zero = V::zero();
  V J[7];
  J[0] = dxf * iz;
  J[1] = dyf * iz;
  J[2] = zero - iz * (dxf * nx + dyf * ny);
  J[3] = zero - dxf * nx * ny - dyf * (one + ny * ny);
  J[4] = dxf * (one + nx * nx) + dyf * nx * ny;
  J[5] = dyf * nx - dxf * ny;
  J[6] = zero - ref;
  // J[7] = -1: its products are sign flips.
  LDSM_SIMD_UNROLL
  for (int i = 0; i < 7; ++i) {
    const V wj = w * J[i];
    LDSM_SIMD_UNROLL
    for (int j = i; j < 7; ++j, ++acc) *acc = *acc + wj * J[j];
    *acc = *acc - wj;  // (i, 7)
    ++acc;
  }
  *acc = *acc + w;  // (7, 7)
  ++acc;
  const V wr = w * r;
  LDSM_SIMD_UNROLL
  for (int i = 0; i < 7; ++i, ++acc) *acc = *acc + wr * J[i];
  *acc = *acc - wr;
}

template <class V>
inline void coarseFlush(V* acc, double* sums) {
  LDSM_SIMD_UNROLL
  for (int k = 0; k < kCoarseSums; k += 4) {
    alignas(16) float f[4];
    sum4(acc[k], acc[k + 1], acc[k + 2], acc[k + 3]).store(f);
    LDSM_SIMD_UNROLL
    for (int i = 0; i < 4; ++i) {
      sums[k + i] += static_cast<double>(f[i]);
      acc[k + i] = V::zero();
    }
  }
}

}  // namespace detail

/// Sums over all residuals into `sums`: [coarseUpperIndex(i, j)] = sum w J_i J_j,
/// [kCoarseUpper + i] = sum w J_i r (overwritten). Float lane sums cover blocks of kBlock
/// residuals (kBlock / 4 per lane).
template <class V>
inline void accumulateCoarseSystem(const CoarseResidualArrays& a, double sums[kCoarseSums]) {
  constexpr int kBlock = 256;
  V acc[kCoarseSums];
  for (V& v : acc) v = V::zero();
  for (int k = 0; k < kCoarseSums; ++k) sums[k] = 0.0;
  const int full = a.count & ~3;
  for (int begin = 0; begin < full; begin += kBlock) {
    const int end = std::min(begin + kBlock, full);
    for (int i = begin; i < end; i += 4) {
      detail::coarseAccumulate4(V::loadu(a.dx_fx + i), V::loadu(a.dy_fy + i), V::loadu(a.nx + i),
                                V::loadu(a.ny + i), V::loadu(a.iz + i), V::loadu(a.ref_term + i),
                                V::loadu(a.residual + i), V::loadu(a.weight + i), acc);
    }
    detail::coarseFlush(acc, sums);
  }
  if (full < a.count) {  // the last 1..3 residuals, zero-weight padded
    alignas(16) float t[8][4] = {};
    const float* src[8] = {a.dx_fx, a.dy_fy, a.nx, a.ny, a.iz, a.ref_term, a.residual, a.weight};
    for (int s = 0; s < 8; ++s)
      for (int i = full; i < a.count; ++i) t[s][i - full] = src[s][i];
    detail::coarseAccumulate4(V::load(t[0]), V::load(t[1]), V::load(t[2]), V::load(t[3]),
                              V::load(t[4]), V::load(t[5]), V::load(t[6]), V::load(t[7]), acc);
    detail::coarseFlush(acc, sums);
  }
}

}  // namespace simd
}  // namespace ldsm
