// A row's saturation mask: out[x] = 1 where in[x] >= level, else 0 (NaN: 0). markAtLeastRow<V>
// compares four pixels per vector and writes their four bytes at once (V from math/simd/vec4f.h);
// reference::markAtLeastRow is the per-pixel formulation. A comparison is exact, so the two agree
// on every input (tested for every vector type).
#pragma once

#include <cstdint>
#include <cstring>

#include "math/simd/vec4f.h"

namespace ldsm {
namespace simd {
namespace reference {

inline void markAtLeastRow(const float* in, int n, float level, std::uint8_t* out) {
  for (int x = 0; x < n; ++x) out[x] = in[x] >= level ? 1 : 0;
}

}  // namespace reference

template <class V>
inline void markAtLeastRow(const float* in, int n, float level, std::uint8_t* out) {
  // The four bytes of lane bits b, little end first: byte k is bit k of b.
  static constexpr std::uint8_t kBytes[16][4] = {
      {0, 0, 0, 0}, {1, 0, 0, 0}, {0, 1, 0, 0}, {1, 1, 0, 0}, {0, 0, 1, 0}, {1, 0, 1, 0},
      {0, 1, 1, 0}, {1, 1, 1, 0}, {0, 0, 0, 1}, {1, 0, 0, 1}, {0, 1, 0, 1}, {1, 1, 0, 1},
      {0, 0, 1, 1}, {1, 0, 1, 1}, {0, 1, 1, 1}, {1, 1, 1, 1}};
  const V l = V::set1(level);
  int x = 0;
  for (; x + 4 <= n; x += 4) std::memcpy(out + x, kBytes[laneBits(V::loadu(in + x) >= l)], 4);
  reference::markAtLeastRow(in + x, n - x, level, out + x);
}

}  // namespace simd
}  // namespace ldsm
