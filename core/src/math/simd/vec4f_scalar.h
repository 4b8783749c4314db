// Portable four-float vector in plain C++: the fallback of vec4f.h when no SIMD instruction set
// is selected, and a reference for the SSE and NEON versions (same interface, see vec4f.h).
#pragma once

#include <cmath>
#include <cstdint>

namespace ldsm {
namespace simd {

struct Mask4Scalar {
  bool m[4];
};

struct alignas(16) Vec4Scalar {
  using Mask = Mask4Scalar;
  float v[4];

  static Vec4Scalar load(const float* p) { return {{p[0], p[1], p[2], p[3]}}; }
  static Vec4Scalar loadu(const float* p) { return {{p[0], p[1], p[2], p[3]}}; }
  /// Four int16 converted to float.
  static Vec4Scalar loadInt16(const std::int16_t* p) {
    return {{static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2]),
             static_cast<float>(p[3])}};
  }
  static Vec4Scalar set1(float x) { return {{x, x, x, x}}; }
  static Vec4Scalar setLanes(float a, float b, float c, float d) { return {{a, b, c, d}}; }
  static Vec4Scalar zero() { return {{0.f, 0.f, 0.f, 0.f}}; }
  void store(float* p) const {
    for (int i = 0; i < 4; ++i) p[i] = v[i];
  }
  void storeu(float* p) const { store(p); }
  /// Stores the four lanes, integers within the int16 range, as int16.
  void storeInt16(std::int16_t* p) const {
    for (int i = 0; i < 4; ++i) p[i] = static_cast<std::int16_t>(static_cast<int>(v[i]));
  }
};

#define LDSM_VEC4_SCALAR_BINARY(op)                                                    \
  inline Vec4Scalar operator op(const Vec4Scalar& a, const Vec4Scalar& b) {            \
    return {{a.v[0] op b.v[0], a.v[1] op b.v[1], a.v[2] op b.v[2], a.v[3] op b.v[3]}}; \
  }
LDSM_VEC4_SCALAR_BINARY(+)
LDSM_VEC4_SCALAR_BINARY(-)
LDSM_VEC4_SCALAR_BINARY(*)
LDSM_VEC4_SCALAR_BINARY(/)
#undef LDSM_VEC4_SCALAR_BINARY

#define LDSM_VEC4_SCALAR_COMPARE(op)                                                   \
  inline Mask4Scalar operator op(const Vec4Scalar& a, const Vec4Scalar& b) {           \
    return {{a.v[0] op b.v[0], a.v[1] op b.v[1], a.v[2] op b.v[2], a.v[3] op b.v[3]}}; \
  }
LDSM_VEC4_SCALAR_COMPARE(<)
LDSM_VEC4_SCALAR_COMPARE(>)
LDSM_VEC4_SCALAR_COMPARE(>=)
#undef LDSM_VEC4_SCALAR_COMPARE

inline Mask4Scalar operator&(const Mask4Scalar& a, const Mask4Scalar& b) {
  return {{a.m[0] && b.m[0], a.m[1] && b.m[1], a.m[2] && b.m[2], a.m[3] && b.m[3]}};
}
inline bool allOf(const Mask4Scalar& a) {
  return a.m[0] && a.m[1] && a.m[2] && a.m[3];
}
inline int laneBits(const Mask4Scalar& a) {
  return (a.m[0] ? 1 : 0) | (a.m[1] ? 2 : 0) | (a.m[2] ? 4 : 0) | (a.m[3] ? 8 : 0);
}
inline Vec4Scalar select(const Mask4Scalar& m, const Vec4Scalar& a, const Vec4Scalar& b) {
  return {{m.m[0] ? a.v[0] : b.v[0], m.m[1] ? a.v[1] : b.v[1], m.m[2] ? a.v[2] : b.v[2],
           m.m[3] ? a.v[3] : b.v[3]}};
}
inline Vec4Scalar squareRoot(const Vec4Scalar& a) {
  return {{std::sqrt(a.v[0]), std::sqrt(a.v[1]), std::sqrt(a.v[2]), std::sqrt(a.v[3])}};
}
/// The larger of each pair of lanes (for lanes that are not NaN).
inline Vec4Scalar maximum(const Vec4Scalar& a, const Vec4Scalar& b) {
  return {{a.v[0] > b.v[0] ? a.v[0] : b.v[0], a.v[1] > b.v[1] ? a.v[1] : b.v[1],
           a.v[2] > b.v[2] ? a.v[2] : b.v[2], a.v[3] > b.v[3] ? a.v[3] : b.v[3]}};
}
inline Vec4Scalar absolute(const Vec4Scalar& a) {
  return {{std::fabs(a.v[0]), std::fabs(a.v[1]), std::fabs(a.v[2]), std::fabs(a.v[3])}};
}
/// Truncates towards zero; stores the integers in `ints` and returns them as floats. Lanes must
/// be within the int32 range.
inline Vec4Scalar truncate(const Vec4Scalar& a, std::int32_t* ints) {
  Vec4Scalar r;
  for (int i = 0; i < 4; ++i) {
    ints[i] = static_cast<std::int32_t>(a.v[i]);
    r.v[i] = static_cast<float>(ints[i]);
  }
  return r;
}
/// (a1, a2, a3, 0).
inline Vec4Scalar shiftDown1(const Vec4Scalar& a) {
  return {{a.v[1], a.v[2], a.v[3], 0.f}};
}
/// All lanes set to lane K of a.
template <int K>
inline Vec4Scalar broadcast(const Vec4Scalar& a) {
  static_assert(K >= 0 && K < 4, "lane index");
  return Vec4Scalar::set1(a.v[K]);
}
/// Transposes the 4x4 matrix whose rows are a, b, c, d.
inline void transpose4(Vec4Scalar& a, Vec4Scalar& b, Vec4Scalar& c, Vec4Scalar& d) {
  const Vec4Scalar r0{{a.v[0], b.v[0], c.v[0], d.v[0]}};
  const Vec4Scalar r1{{a.v[1], b.v[1], c.v[1], d.v[1]}};
  const Vec4Scalar r2{{a.v[2], b.v[2], c.v[2], d.v[2]}};
  const Vec4Scalar r3{{a.v[3], b.v[3], c.v[3], d.v[3]}};
  a = r0;
  b = r1;
  c = r2;
  d = r3;
}
/// (sum of a's lanes, sum of b's, sum of c's, sum of d's).
inline Vec4Scalar sum4(const Vec4Scalar& a, const Vec4Scalar& b, const Vec4Scalar& c,
                       const Vec4Scalar& d) {
  return {{(a.v[0] + a.v[2]) + (a.v[1] + a.v[3]), (b.v[0] + b.v[2]) + (b.v[1] + b.v[3]),
           (c.v[0] + c.v[2]) + (c.v[1] + c.v[3]), (d.v[0] + d.v[2]) + (d.v[1] + d.v[3])}};
}
inline float horizontalSum(const Vec4Scalar& a) {
  return (a.v[0] + a.v[2]) + (a.v[1] + a.v[3]);
}

}  // namespace simd
}  // namespace ldsm
