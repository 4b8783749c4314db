// The two passes of CompactPlane::encode over a row of floats: the largest magnitude (and whether
// every value is finite), then each value as round(value / step) in int16, ties to even (adding
// and subtracting 1.5 * 2^23 rounds a float below 2^22 in magnitude to the nearest integer without
// a branch). The SIMD kernels (V from math/simd/vec4f.h) do four values at a time; the reference
// functions are the per-value formulation. Both give the same int16 values, the same largest
// magnitude and the same finiteness (tested for every vector type).
#pragma once

#include <cmath>
#include <cstdint>

#include "math/simd/vec4f.h"

namespace ldsm {
namespace simd {

/// 1.5 * 2^23 (see above).
inline constexpr float kRoundingBias = 12582912.f;

/// The largest magnitude of a run of values, and a sum that stays 0 unless one of them is NaN or
/// infinite (v * 0 is NaN then).
struct PlaneRange {
  float max_abs = 0.f;
  float zero = 0.f;
  bool finite() const { return zero == 0.f; }
};

namespace reference {

inline void addToRange(const float* v, int n, PlaneRange& range) {
  for (int i = 0; i < n; ++i) {
    const float a = std::fabs(v[i]);
    range.max_abs = a > range.max_abs ? a : range.max_abs;
    range.zero += v[i] * 0.f;
  }
}

/// round(v / step) for |v / step| <= 32767 (v * inv_step is exact: inv_step a power of two).
inline void quantizeRow(const float* in, int n, float inv_step, std::int16_t* out) {
  for (int i = 0; i < n; ++i) {
    const float s = in[i] * inv_step;
    out[i] = static_cast<std::int16_t>(static_cast<int>((s + kRoundingBias) - kRoundingBias));
  }
}

}  // namespace reference

template <class V>
inline void addToRange(const float* v, int n, PlaneRange& range) {
  V m = V::zero(), z = V::zero();
  const V zero = V::zero();
  int i = 0;
  for (; i + 4 <= n; i += 4) {
    const V x = V::loadu(v + i);
    m = maximum(m, absolute(x));
    z = z + x * zero;
  }
  alignas(16) float lanes_m[4], lanes_z[4];
  m.store(lanes_m);
  z.store(lanes_z);
  for (int k = 0; k < 4; ++k) {
    range.max_abs = lanes_m[k] > range.max_abs ? lanes_m[k] : range.max_abs;
    range.zero += lanes_z[k];
  }
  reference::addToRange(v + i, n - i, range);
}

template <class V>
inline void quantizeRow(const float* in, int n, float inv_step, std::int16_t* out) {
  const V inv = V::set1(inv_step), bias = V::set1(kRoundingBias);
  int i = 0;
  for (; i + 4 <= n; i += 4) ((V::loadu(in + i) * inv + bias) - bias).storeInt16(out + i);
  reference::quantizeRow(in + i, n - i, inv_step, out + i);
}

}  // namespace simd
}  // namespace ldsm
