// One row of a pyramid level's packed (intensity, dx, dy) plane from its intensity row and the
// rows above and below (null on the image border): central differences
//   dx = 0.5 (I(x+1) - I(x-1)),  dy = 0.5 (I_below(x) - I_above(x)),
// zero on the one-pixel border. gradientRow<V> computes four inner pixels per vector and writes
// them packed (V from math/simd/vec4f.h); reference::gradientRow is the per-pixel formulation with
// the same operations, so the two are bit-identical (tested for every vector type).
#pragma once

#include "image/gradient_pixel.h"
#include "math/simd/vec4f.h"

namespace ldsm {
namespace simd {
namespace reference {

inline void gradientRow(const float* up, const float* row, const float* down, int w,
                        GradientPixel* out) {
  if (up == nullptr || down == nullptr) {
    for (int x = 0; x < w; ++x) out[x] = {row[x], 0.f, 0.f};
    return;
  }
  if (w <= 0) return;
  out[0] = {row[0], 0.f, 0.f};
  for (int x = 1; x < w - 1; ++x) {
    out[x] = {row[x], 0.5f * (row[x + 1] - row[x - 1]), 0.5f * (down[x] - up[x])};
  }
  if (w > 1) out[w - 1] = {row[w - 1], 0.f, 0.f};
}

}  // namespace reference

template <class V>
inline void gradientRow(const float* up, const float* row, const float* down, int w,
                        GradientPixel* out) {
  if (up == nullptr || down == nullptr || w < 6) {
    reference::gradientRow(up, row, down, w, out);
    return;
  }
  out[0] = {row[0], 0.f, 0.f};
  const V half = V::set1(0.5f);
  int x = 1;
  // Four pixels as four (I, dx, dy, -) vectors, stored 12 bytes apart: each store's fourth float
  // lands on the next pixel's intensity, which a later store writes (the next block, the tail or
  // the last pixel, hence x + 4 <= w - 1).
  for (; x + 4 <= w - 1; x += 4) {
    V i = V::loadu(row + x);
    V dx = half * (V::loadu(row + x + 1) - V::loadu(row + x - 1));
    V dy = half * (V::loadu(down + x) - V::loadu(up + x));
    V unused = V::zero();
    transpose4(i, dx, dy, unused);
    float* p = &out[x].intensity;
    i.storeu(p);
    dx.storeu(p + 3);
    dy.storeu(p + 6);
    unused.storeu(p + 9);
  }
  for (; x < w - 1; ++x) {
    out[x] = {row[x], 0.5f * (row[x + 1] - row[x - 1]), 0.5f * (down[x] - up[x])};
  }
  out[w - 1] = {row[w - 1], 0.f, 0.f};
}

}  // namespace simd
}  // namespace ldsm
