// Four-float vector on NEON, for AArch64 and ARMv7 (which lacks vector division, square root and
// across-vector adds: division goes lane by lane, the square root is a reciprocal square-root
// estimate refined by two Newton steps, reductions use pairwise adds). Same interface as
// Vec4Scalar, see vec4f.h.
#pragma once

#include <arm_neon.h>

#include <cstdint>

namespace ldsm {
namespace simd {

struct Mask4Neon {
  uint32x4_t n;
};

struct Vec4Neon {
  using Mask = Mask4Neon;
  float32x4_t n;

  static Vec4Neon load(const float* p) { return {vld1q_f32(p)}; }
  static Vec4Neon loadu(const float* p) { return {vld1q_f32(p)}; }
  /// Four int16 (8 bytes, 2-byte aligned) converted to float.
  static Vec4Neon loadInt16(const std::int16_t* p) {
    return {vcvtq_f32_s32(vmovl_s16(vld1_s16(p)))};
  }
  static Vec4Neon set1(float x) { return {vdupq_n_f32(x)}; }
  /// Lanes (a, b, c, d) from registers (lane inserts), not through memory.
  static Vec4Neon setLanes(float a, float b, float c, float d) {
    return {vcombine_f32(vset_lane_f32(b, vdup_n_f32(a), 1), vset_lane_f32(d, vdup_n_f32(c), 1))};
  }
  static Vec4Neon zero() { return {vdupq_n_f32(0.f)}; }
  void store(float* p) const { vst1q_f32(p, n); }
  void storeu(float* p) const { vst1q_f32(p, n); }
  /// Stores the four lanes, integers within the int16 range, as int16 (8 bytes, unaligned).
  void storeInt16(std::int16_t* p) const { vst1_s16(p, vmovn_s32(vcvtq_s32_f32(n))); }
};

inline Vec4Neon operator+(Vec4Neon a, Vec4Neon b) {
  return {vaddq_f32(a.n, b.n)};
}
inline Vec4Neon operator-(Vec4Neon a, Vec4Neon b) {
  return {vsubq_f32(a.n, b.n)};
}
inline Vec4Neon operator*(Vec4Neon a, Vec4Neon b) {
  return {vmulq_f32(a.n, b.n)};
}
inline Vec4Neon operator/(Vec4Neon a, Vec4Neon b) {
#if defined(__aarch64__)
  return {vdivq_f32(a.n, b.n)};
#else
  // Lane by lane on the VFP: a refined reciprocal estimate is a few ulp off, which moves
  // projected pixel positions (divisions by depth) by more than the kernels' tolerance.
  alignas(16) float x[4], y[4];
  vst1q_f32(x, a.n);
  vst1q_f32(y, b.n);
  for (int i = 0; i < 4; ++i) x[i] /= y[i];
  return {vld1q_f32(x)};
#endif
}
inline Mask4Neon operator<(Vec4Neon a, Vec4Neon b) {
  return {vcltq_f32(a.n, b.n)};
}
inline Mask4Neon operator>(Vec4Neon a, Vec4Neon b) {
  return {vcgtq_f32(a.n, b.n)};
}
inline Mask4Neon operator>=(Vec4Neon a, Vec4Neon b) {
  return {vcgeq_f32(a.n, b.n)};
}
inline Mask4Neon operator&(Mask4Neon a, Mask4Neon b) {
  return {vandq_u32(a.n, b.n)};
}
inline bool allOf(Mask4Neon a) {
  const uint32x2_t m = vand_u32(vget_low_u32(a.n), vget_high_u32(a.n));
  return vget_lane_u32(vpmin_u32(m, m), 0) != 0u;
}
inline int laneBits(Mask4Neon a) {
  alignas(16) std::uint32_t m[4];
  vst1q_u32(m, a.n);
  return static_cast<int>((m[0] & 1u) | ((m[1] & 1u) << 1) | ((m[2] & 1u) << 2) |
                          ((m[3] & 1u) << 3));
}
inline Vec4Neon select(Mask4Neon m, Vec4Neon a, Vec4Neon b) {
  return {vbslq_f32(m.n, a.n, b.n)};
}
inline Vec4Neon squareRoot(Vec4Neon a) {
#if defined(__aarch64__)
  return {vsqrtq_f32(a.n)};
#else
  float32x4_t r = vrsqrteq_f32(a.n);  // 1/sqrt(a), refined twice
  r = vmulq_f32(vrsqrtsq_f32(vmulq_f32(a.n, r), r), r);
  r = vmulq_f32(vrsqrtsq_f32(vmulq_f32(a.n, r), r), r);
  const uint32x4_t positive = vcgtq_f32(a.n, vdupq_n_f32(0.f));
  return {vbslq_f32(positive, vmulq_f32(a.n, r), vdupq_n_f32(0.f))};
#endif
}
inline Vec4Neon maximum(Vec4Neon a, Vec4Neon b) {
  return {vmaxq_f32(a.n, b.n)};
}
inline Vec4Neon absolute(Vec4Neon a) {
  return {vabsq_f32(a.n)};
}
inline Vec4Neon truncate(Vec4Neon a, std::int32_t* ints) {
  const int32x4_t i = vcvtq_s32_f32(a.n);
  vst1q_s32(ints, i);
  return {vcvtq_f32_s32(i)};
}
inline Vec4Neon shiftDown1(Vec4Neon a) {
  return {vextq_f32(a.n, vdupq_n_f32(0.f), 1)};
}
template <int K>
inline Vec4Neon broadcast(Vec4Neon a) {
  static_assert(K >= 0 && K < 4, "lane index");
  if constexpr (K < 2) {
    return {vdupq_lane_f32(vget_low_f32(a.n), K)};
  } else {
    return {vdupq_lane_f32(vget_high_f32(a.n), K - 2)};
  }
}
inline void transpose4(Vec4Neon& a, Vec4Neon& b, Vec4Neon& c, Vec4Neon& d) {
  const float32x4x2_t ab = vtrnq_f32(a.n, b.n);  // (a0 b0 a2 b2), (a1 b1 a3 b3)
  const float32x4x2_t cd = vtrnq_f32(c.n, d.n);  // (c0 d0 c2 d2), (c1 d1 c3 d3)
  a.n = vcombine_f32(vget_low_f32(ab.val[0]), vget_low_f32(cd.val[0]));
  b.n = vcombine_f32(vget_low_f32(ab.val[1]), vget_low_f32(cd.val[1]));
  c.n = vcombine_f32(vget_high_f32(ab.val[0]), vget_high_f32(cd.val[0]));
  d.n = vcombine_f32(vget_high_f32(ab.val[1]), vget_high_f32(cd.val[1]));
}
inline Vec4Neon sum4(Vec4Neon a, Vec4Neon b, Vec4Neon c, Vec4Neon d) {
  // Pairwise adds: (a0+a1, a2+a3) -> (sum a, sum b); ARMv7 has no vaddvq.
  const float32x2_t sa = vpadd_f32(vget_low_f32(a.n), vget_high_f32(a.n));
  const float32x2_t sb = vpadd_f32(vget_low_f32(b.n), vget_high_f32(b.n));
  const float32x2_t sc = vpadd_f32(vget_low_f32(c.n), vget_high_f32(c.n));
  const float32x2_t sd = vpadd_f32(vget_low_f32(d.n), vget_high_f32(d.n));
  return {vcombine_f32(vpadd_f32(sa, sb), vpadd_f32(sc, sd))};
}
inline float horizontalSum(Vec4Neon a) {
  const float32x2_t s = vpadd_f32(vget_low_f32(a.n), vget_high_f32(a.n));
  return vget_lane_f32(vpadd_f32(s, s), 0);
}

}  // namespace simd
}  // namespace ldsm
