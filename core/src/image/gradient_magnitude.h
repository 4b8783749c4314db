// Squared gradient magnitudes of a packed (intensity, dx, dy) row, dx^2 + dy^2 per pixel, and
// their histogram bins min(floor(sqrt(.)), bins - 1). The SIMD kernels (V from math/simd/vec4f.h)
// read four packed pixels as four 4-float loads transposed into intensity, dx and dy; the
// reference functions are the per-pixel formulation with the same operations, so the two agree
// bit for bit (tested for every vector type).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "image/gradient_pixel.h"
#include "math/simd/vec4f.h"

namespace ldsm {
namespace simd {
namespace reference {

inline void gradientMagnitudeSqRow(const GradientPixel* row, int n, float* out) {
  for (int i = 0; i < n; ++i) out[i] = row[i].dx * row[i].dx + row[i].dy * row[i].dy;
}

inline void gradientMagnitudeBinRow(const GradientPixel* row, int n, int max_bin,
                                    std::int32_t* bins) {
  for (int i = 0; i < n; ++i) {
    const float mag = std::sqrt(row[i].dx * row[i].dx + row[i].dy * row[i].dy);
    bins[i] = std::min(static_cast<int>(mag), max_bin);
  }
}

}  // namespace reference

namespace detail {

/// dx^2 + dy^2 of the four pixels at `p`; reads the float after the fourth pixel too.
template <class V>
inline V magnitudeSq4(const GradientPixel* p) {
  const float* f = &p->intensity;
  V i = V::loadu(f), dx = V::loadu(f + 3), dy = V::loadu(f + 6), rest = V::loadu(f + 9);
  transpose4(i, dx, dy, rest);
  return dx * dx + dy * dy;
}

}  // namespace detail

/// The row's first n pixels (four at a time while a fifth follows: the loads of four pixels read
/// the next one's intensity; the rest per pixel).
template <class V>
inline void gradientMagnitudeSqRow(const GradientPixel* row, int n, float* out) {
  int i = 0;
  for (; i + 4 < n; i += 4) detail::magnitudeSq4<V>(row + i).storeu(out + i);
  reference::gradientMagnitudeSqRow(row + i, n - i, out + i);
}

template <class V>
inline void gradientMagnitudeBinRow(const GradientPixel* row, int n, int max_bin,
                                    std::int32_t* bins) {
  const V top = V::set1(static_cast<float>(max_bin));
  int i = 0;
  for (; i + 4 < n; i += 4) {
    const V mag = squareRoot(detail::magnitudeSq4<V>(row + i));
    // min(floor(mag), max_bin) == floor(min(mag, max_bin)) for mag >= 0.
    truncate(select(mag > top, top, mag), bins + i);
  }
  reference::gradientMagnitudeBinRow(row + i, n - i, max_bin, bins + i);
}

}  // namespace simd
}  // namespace ldsm
