// Four-float vector on SSE2 (the x86-64 baseline; nothing newer is required). Same interface as
// Vec4Scalar, see vec4f.h.
#pragma once

#include <emmintrin.h>

#include <cstdint>

namespace ldsm {
namespace simd {

struct Mask4Sse {
  __m128 n;
};

struct Vec4Sse {
  using Mask = Mask4Sse;
  __m128 n;

  static Vec4Sse load(const float* p) { return {_mm_load_ps(p)}; }
  static Vec4Sse loadu(const float* p) { return {_mm_loadu_ps(p)}; }
  /// Four int16 (8 bytes, unaligned) converted to float.
  static Vec4Sse loadInt16(const std::int16_t* p) {
    const __m128i x = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(p));
    return {_mm_cvtepi32_ps(_mm_srai_epi32(_mm_unpacklo_epi16(x, x), 16))};
  }
  static Vec4Sse set1(float x) { return {_mm_set1_ps(x)}; }
  /// Lanes (a, b, c, d) from registers (shuffles): no store to memory and reload (a wide load
  /// cannot be forwarded from four narrow stores and waits until they are written).
  static Vec4Sse setLanes(float a, float b, float c, float d) { return {_mm_setr_ps(a, b, c, d)}; }
  static Vec4Sse zero() { return {_mm_setzero_ps()}; }
  void store(float* p) const { _mm_store_ps(p, n); }
  void storeu(float* p) const { _mm_storeu_ps(p, n); }
  /// Stores the four lanes, integers within the int16 range, as int16 (8 bytes, unaligned).
  void storeInt16(std::int16_t* p) const {
    const __m128i i = _mm_cvttps_epi32(n);
    _mm_storel_epi64(reinterpret_cast<__m128i*>(p), _mm_packs_epi32(i, i));
  }
};

inline Vec4Sse operator+(Vec4Sse a, Vec4Sse b) {
  return {_mm_add_ps(a.n, b.n)};
}
inline Vec4Sse operator-(Vec4Sse a, Vec4Sse b) {
  return {_mm_sub_ps(a.n, b.n)};
}
inline Vec4Sse operator*(Vec4Sse a, Vec4Sse b) {
  return {_mm_mul_ps(a.n, b.n)};
}
inline Vec4Sse operator/(Vec4Sse a, Vec4Sse b) {
  return {_mm_div_ps(a.n, b.n)};
}
inline Mask4Sse operator<(Vec4Sse a, Vec4Sse b) {
  return {_mm_cmplt_ps(a.n, b.n)};
}
inline Mask4Sse operator>(Vec4Sse a, Vec4Sse b) {
  return {_mm_cmpgt_ps(a.n, b.n)};
}
inline Mask4Sse operator>=(Vec4Sse a, Vec4Sse b) {
  return {_mm_cmpge_ps(a.n, b.n)};
}
inline Mask4Sse operator&(Mask4Sse a, Mask4Sse b) {
  return {_mm_and_ps(a.n, b.n)};
}
inline bool allOf(Mask4Sse a) {
  return _mm_movemask_ps(a.n) == 0xF;
}
inline int laneBits(Mask4Sse a) {
  return _mm_movemask_ps(a.n);
}
inline Vec4Sse select(Mask4Sse m, Vec4Sse a, Vec4Sse b) {
  return {_mm_or_ps(_mm_and_ps(m.n, a.n), _mm_andnot_ps(m.n, b.n))};
}
inline Vec4Sse squareRoot(Vec4Sse a) {
  return {_mm_sqrt_ps(a.n)};
}
inline Vec4Sse maximum(Vec4Sse a, Vec4Sse b) {
  return {_mm_max_ps(a.n, b.n)};
}
inline Vec4Sse absolute(Vec4Sse a) {
  return {_mm_andnot_ps(_mm_set1_ps(-0.f), a.n)};
}
inline Vec4Sse truncate(Vec4Sse a, std::int32_t* ints) {
  const __m128i i = _mm_cvttps_epi32(a.n);
  _mm_storeu_si128(reinterpret_cast<__m128i*>(ints), i);
  return {_mm_cvtepi32_ps(i)};
}
inline Vec4Sse shiftDown1(Vec4Sse a) {
  return {_mm_castsi128_ps(_mm_srli_si128(_mm_castps_si128(a.n), 4))};
}
template <int K>
inline Vec4Sse broadcast(Vec4Sse a) {
  static_assert(K >= 0 && K < 4, "lane index");
  return {_mm_shuffle_ps(a.n, a.n, _MM_SHUFFLE(K, K, K, K))};
}
inline void transpose4(Vec4Sse& a, Vec4Sse& b, Vec4Sse& c, Vec4Sse& d) {
  const __m128 t0 = _mm_unpacklo_ps(a.n, b.n);  // a0 b0 a1 b1
  const __m128 t1 = _mm_unpackhi_ps(a.n, b.n);  // a2 b2 a3 b3
  const __m128 t2 = _mm_unpacklo_ps(c.n, d.n);  // c0 d0 c1 d1
  const __m128 t3 = _mm_unpackhi_ps(c.n, d.n);  // c2 d2 c3 d3
  a.n = _mm_movelh_ps(t0, t2);
  b.n = _mm_movehl_ps(t2, t0);
  c.n = _mm_movelh_ps(t1, t3);
  d.n = _mm_movehl_ps(t3, t1);
}
inline Vec4Sse sum4(Vec4Sse a, Vec4Sse b, Vec4Sse c, Vec4Sse d) {
  // (a0+a2, b0+b2, a1+a3, b1+b3) and the same for c, d; then fold the halves.
  const __m128 ab = _mm_add_ps(_mm_unpacklo_ps(a.n, b.n), _mm_unpackhi_ps(a.n, b.n));
  const __m128 cd = _mm_add_ps(_mm_unpacklo_ps(c.n, d.n), _mm_unpackhi_ps(c.n, d.n));
  return {_mm_add_ps(_mm_movelh_ps(ab, cd), _mm_movehl_ps(cd, ab))};
}
inline float horizontalSum(Vec4Sse a) {
  const __m128 s = _mm_add_ps(a.n, _mm_movehl_ps(a.n, a.n));  // a0+a2, a1+a3
  return _mm_cvtss_f32(_mm_add_ss(s, _mm_shuffle_ps(s, s, _MM_SHUFFLE(1, 1, 1, 1))));
}

}  // namespace simd
}  // namespace ldsm
