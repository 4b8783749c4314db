// One row of the corner detector's local-maximum test on its score image: pixel x of row `s`
// (rows `above` and `below` around it) is a candidate when its score v is positive, at least
// `min_score`, strictly above the neighbours that come earlier in raster order and at least equal
// to the later ones (exactly one pixel of a plateau survives). localMaximaRow<V> tests four pixels
// per vector (V from math/simd/vec4f.h) and reports the candidates in increasing x;
// reference::localMaximaRow is the per-pixel test. Both report the same pixels in the same order
// (tested for every vector type).
#pragma once

#include "math/simd/vec4f.h"

namespace ldsm {
namespace simd {
namespace reference {

/// Calls found(x, v) for every candidate x in [x_begin, x_end) in increasing x. Reads x - 1 and
/// x + 1 of the three rows.
template <class Found>
inline void localMaximaRow(const float* above, const float* s, const float* below, int x_begin,
                           int x_end, float min_score, Found&& found) {
  for (int x = x_begin; x < x_end; ++x) {
    const float v = s[x];
    if (v <= 0.f || v < min_score) continue;
    if (!(v > above[x - 1] && v > above[x] && v > above[x + 1] && v > s[x - 1])) continue;
    if (!(v >= s[x + 1] && v >= below[x - 1] && v >= below[x] && v >= below[x + 1])) continue;
    found(x, v);
  }
}

}  // namespace reference

template <class V, class Found>
inline void localMaximaRow(const float* above, const float* s, const float* below, int x_begin,
                           int x_end, float min_score, Found&& found) {
  const V zero = V::zero();
  const V floor = V::set1(min_score);
  int x = x_begin;
  for (; x + 4 <= x_end; x += 4) {
    const V v = V::loadu(s + x);
    // For a non-NaN v, "not (v <= 0 or v < min_score)" is (v > 0 and v >= min_score); a NaN score
    // fails every ordered comparison in both forms.
    typename V::Mask m = (v > zero) & (v >= floor);
    if (laneBits(m) == 0) continue;
    m = m & (v > V::loadu(above + x - 1)) & (v > V::loadu(above + x)) &
        (v > V::loadu(above + x + 1)) & (v > V::loadu(s + x - 1));
    m = m & (v >= V::loadu(s + x + 1)) & (v >= V::loadu(below + x - 1)) &
        (v >= V::loadu(below + x)) & (v >= V::loadu(below + x + 1));
    const int bits = laneBits(m);
    if (bits == 0) continue;
    for (int k = 0; k < 4; ++k)
      if (bits & (1 << k)) found(x + k, s[x + k]);
  }
  reference::localMaximaRow(above, s, below, x, x_end, min_score, found);
}

}  // namespace simd
}  // namespace ldsm
