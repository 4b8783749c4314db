// Second half of a photometric residual's evaluation: the Gauss-Newton terms of the 8 pattern
// pixels, summed over the pixels as SIMD lanes.
//
// The residual's Jacobian row over [eps (6), a_h, b_h, a_t, b_t | inverse depth] is
//   [ (gx, gy) dpx/deps,  scale (I_h - b_h),  scale,  -scale (I_h - b_h),  -1 | (gx, gy) dpx/dd ]
// so every relative row is a multiple of one of the 8 basis rows u = [eps (6), a_h, 1]. The
// (host, target) pair block therefore needs only sum w u u^T (36 upper-triangle values) and
// sum w r u (8): PatternPairSums keeps them as per-lane float partial sums (no horizontal sum
// per residual), moves them into double every kFlushInterval residuals, and totals() reduces
// them once per pair. The point's terms (coupling sum w u J_d, H_dd, b_d) are reduced per
// residual. reference:: holds the plain per-pixel double-precision formulation.
#pragma once

#include "kernels/pattern_sampling.h"
#include "math/simd/vec4f.h"

namespace ldsm {
namespace simd {

constexpr int kPatternBasis = 8;                                        ///< u = [eps (6), a_h, 1]
constexpr int kPatternUpper = kPatternBasis * (kPatternBasis + 1) / 2;  ///< 36
constexpr int kPatternPairSums = kPatternUpper + kPatternBasis;         ///< 44
static_assert(kPatternPairSums % 4 == 0, "flushes in groups of four");

/// Index of sum w u_i u_j (i <= j) in the pair sums: the upper triangle, row by row.
constexpr int patternUpperIndex(int i, int j) {
  return i * kPatternBasis - i * (i - 1) / 2 + (j - i);
}
/// Index of sum w r u_i in the pair sums.
constexpr int patternGradientIndex(int i) {
  return kPatternUpper + i;
}

/// The per-residual Jacobian inputs: the centre pixel's geometric Jacobian (first estimates,
/// shared by the pattern) and the affine row.
struct PatternJacobian {
  float dpx_deps[2][6] = {};      ///< d(pixel x, y) / d eps
  float dpx_didepth[2] = {};      ///< d(pixel x, y) / d inverse depth
  const float* colors = nullptr;  ///< kPatternSize host intensities
  float scale = 1.f;              ///< d r / d a_h = scale * (I_h - host_b)
  float host_b = 0.f;
};

/// One residual's point terms, summed over the pattern.
struct PatternPointSums {
  float coupling[kPatternBasis];  ///< sum w u J_d
  float H_dd;                     ///< sum w J_d^2
  float b_d;                      ///< sum w J_d r
};

/// The pair block's sums over every residual added since reset().
template <class V>
class PatternPairSumsT {
 public:
  /// Residuals summed in float per lane (2 pixels each) before they move into double.
  static constexpr int kFlushInterval = 16;

  PatternPairSumsT() { reset(); }

  void reset() {
    for (V& l : lanes_) l = V::zero();
    for (double& s : sums_) s = 0.0;
    pending_ = count_ = 0;
  }

  /// Number of residuals added since reset().
  int count() const { return count_; }

  /// Adds one residual's pattern to the pair sums and returns its point terms in `point`.
  void add(const PatternSamples& s, const PatternJacobian& jac, PatternPointSums& point) {
    V u[2][7];  // basis rows without the constant 1, per half
    V jd[2], w[2], wr[2];
    LDSM_SIMD_UNROLL
    for (int h = 0; h < 2; ++h) {
      const V gx = V::load(s.gx + 4 * h);
      const V gy = V::load(s.gy + 4 * h);
      LDSM_SIMD_UNROLL
      for (int j = 0; j < 6; ++j)
        u[h][j] = gx * V::set1(jac.dpx_deps[0][j]) + gy * V::set1(jac.dpx_deps[1][j]);
      u[h][6] = V::set1(jac.scale) * (V::loadu(jac.colors + 4 * h) - V::set1(jac.host_b));
      jd[h] = gx * V::set1(jac.dpx_didepth[0]) + gy * V::set1(jac.dpx_didepth[1]);
      w[h] = V::load(s.w + 4 * h);
      wr[h] = w[h] * V::load(s.r + 4 * h);
    }
    V* acc = lanes_;
    LDSM_SIMD_UNROLL
    for (int i = 0; i < 7; ++i) {
      const V wu0 = w[0] * u[0][i];
      const V wu1 = w[1] * u[1][i];
      LDSM_SIMD_UNROLL
      for (int j = i; j < 7; ++j, ++acc) *acc = *acc + (wu0 * u[0][j] + wu1 * u[1][j]);
      *acc = *acc + (wu0 + wu1);  // (i, 1)
      ++acc;
    }
    *acc = *acc + (w[0] + w[1]);  // (1, 1)
    ++acc;
    LDSM_SIMD_UNROLL
    for (int i = 0; i < 7; ++i, ++acc) *acc = *acc + (wr[0] * u[0][i] + wr[1] * u[1][i]);
    *acc = *acc + (wr[0] + wr[1]);

    const V wjd0 = w[0] * jd[0];
    const V wjd1 = w[1] * jd[1];
    V c[8];
    LDSM_SIMD_UNROLL
    for (int i = 0; i < 7; ++i) c[i] = wjd0 * u[0][i] + wjd1 * u[1][i];
    c[7] = wjd0 + wjd1;
    sum4(c[0], c[1], c[2], c[3]).storeu(point.coupling);
    sum4(c[4], c[5], c[6], c[7]).storeu(point.coupling + 4);
    alignas(16) float tail[4];
    sum4(wjd0 * jd[0] + wjd1 * jd[1], wr[0] * jd[0] + wr[1] * jd[1], V::zero(), V::zero())
        .store(tail);
    point.H_dd = tail[0];
    point.b_d = tail[1];

    ++count_;
    if (++pending_ == kFlushInterval) flush();
  }

  /// The sums in double: [patternUpperIndex(i, j)] = sum w u_i u_j, [patternGradientIndex(i)]
  /// = sum w r u_i.
  void totals(double out[kPatternPairSums]) const {
    for (int k = 0; k < kPatternPairSums; k += 4) {
      alignas(16) float f[4];
      sum4(lanes_[k], lanes_[k + 1], lanes_[k + 2], lanes_[k + 3]).store(f);
      for (int i = 0; i < 4; ++i) out[k + i] = sums_[k + i] + static_cast<double>(f[i]);
    }
  }

 private:
  void flush() {
    for (int k = 0; k < kPatternPairSums; k += 4) {
      alignas(16) float f[4];
      sum4(lanes_[k], lanes_[k + 1], lanes_[k + 2], lanes_[k + 3]).store(f);
      for (int i = 0; i < 4; ++i) {
        sums_[k + i] += static_cast<double>(f[i]);
        lanes_[k + i] = V::zero();
      }
    }
    pending_ = 0;
  }

  V lanes_[kPatternPairSums];
  double sums_[kPatternPairSums];
  int pending_ = 0;
  int count_ = 0;
};

using PatternPairSums = PatternPairSumsT<Vec4>;

/// The depth-only terms of one residual: H_dd = sum w J_d^2, b_d = sum w J_d r.
template <class V>
inline void accumulateDepthOnly(const PatternSamples& s, const float dpx_didepth[2], float* H_dd,
                                float* b_d) {
  V h = V::zero(), b = V::zero();
  LDSM_SIMD_UNROLL
  for (int k = 0; k < kPatternSize; k += 4) {
    const V jd =
        V::load(s.gx + k) * V::set1(dpx_didepth[0]) + V::load(s.gy + k) * V::set1(dpx_didepth[1]);
    const V wjd = V::load(s.w + k) * jd;
    h = h + wjd * jd;
    b = b + wjd * V::load(s.r + k);
  }
  alignas(16) float f[4];
  sum4(h, b, V::zero(), V::zero()).store(f);
  *H_dd = f[0];
  *b_d = f[1];
}

namespace reference {

/// Basis row u = [eps (6), a_h, 1] and J_d of pattern pixel k.
inline void patternRow(const PatternSamples& s, const PatternJacobian& jac, int k,
                       float u[kPatternBasis], float* jd) {
  for (int j = 0; j < 6; ++j) u[j] = s.gx[k] * jac.dpx_deps[0][j] + s.gy[k] * jac.dpx_deps[1][j];
  u[6] = jac.scale * (jac.colors[k] - jac.host_b);
  u[7] = 1.f;
  *jd = s.gx[k] * jac.dpx_didepth[0] + s.gy[k] * jac.dpx_didepth[1];
}

/// Adds one residual to `pair` (layout of PatternPairSumsT::totals) and returns its point terms
/// as [coupling (8), H_dd, b_d]; double sums of float rows.
inline void accumulatePattern(const PatternSamples& s, const PatternJacobian& jac,
                              double pair[kPatternPairSums], double point[kPatternBasis + 2]) {
  for (int i = 0; i < kPatternBasis + 2; ++i) point[i] = 0.0;
  for (int k = 0; k < kPatternSize; ++k) {
    float u[kPatternBasis], jd;
    patternRow(s, jac, k, u, &jd);
    const double w = s.w[k], r = s.r[k];
    for (int i = 0; i < kPatternBasis; ++i) {
      for (int j = i; j < kPatternBasis; ++j) pair[patternUpperIndex(i, j)] += w * u[i] * u[j];
      pair[patternGradientIndex(i)] += w * r * u[i];
      point[i] += w * u[i] * jd;
    }
    point[kPatternBasis] += w * jd * jd;
    point[kPatternBasis + 1] += w * jd * r;
  }
}

}  // namespace reference
}  // namespace simd
}  // namespace ldsm
