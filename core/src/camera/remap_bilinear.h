// The rectifier's remap of one output row: output pixel u samples the input bilinearly at
// (map_x[u], map_y[u]) (clamped so that the 2x2 block stays in the image; map_x < 0 marks a pixel
// that sees no input, which gets `invalid`):
//   top = p00 + ax (p10 - p00), bottom = p01 + ax (p11 - p01), out = top + ay (bottom - top).
// remapRow<V> does four output pixels per vector (positions and weights in SIMD, the 2x2 blocks
// loaded per pixel; V from math/simd/vec4f.h; 8-bit blocks on SSE2 and NEON as byte pairs
// widened together); reference::remapRow is the per-pixel formulation, with the same operations
// in the same order, so the two are bit-identical (tested for every vector type). A separable table
// (one input row per output row, one input column per output column) has remapSeparableRow, with
// the cells and weights precomputed per column and per row.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "math/simd/vec4f.h"

namespace ldsm {
namespace simd {

/// The input image: `height` rows of `width` pixels, `stride` pixels apart.
template <typename T>
struct RemapInput {
  const T* data;
  std::ptrdiff_t stride;
  int width, height;
  const T* row(int y) const { return data + static_cast<std::ptrdiff_t>(y) * stride; }
};

namespace reference {

template <typename T>
inline void remapRow(const RemapInput<T>& in, const float* map_x, const float* map_y, int width,
                     float invalid, float* out) {
  const int max_x0 = std::max(in.width - 2, 0), max_y0 = std::max(in.height - 2, 0);
  const std::ptrdiff_t dx1 = in.width > 1 ? 1 : 0;
  const std::ptrdiff_t dy1 = in.height > 1 ? in.stride : 0;
  for (int u = 0; u < width; ++u) {
    const float x = map_x[u], y = map_y[u];
    if (x < 0.0f) {
      out[u] = invalid;
      continue;
    }
    const int x0 = std::min(static_cast<int>(x), max_x0);
    const int y0 = std::min(static_cast<int>(y), max_y0);
    const float ax = x - static_cast<float>(x0), ay = y - static_cast<float>(y0);
    const T* p = in.row(y0) + x0;
    const float top = static_cast<float>(p[0]) + ax * (static_cast<float>(p[dx1]) - p[0]);
    const float bottom =
        static_cast<float>(p[dy1]) + ax * (static_cast<float>(p[dy1 + dx1]) - p[dy1]);
    out[u] = top + ay * (bottom - top);
  }
}

}  // namespace reference

namespace detail {

/// top = a + ax (b - a), bottom = c + ax (d - c), top + ay (bottom - top): the blend of the
/// blocks' corners p00 (a), p10 (b), p01 (c), p11 (d).
template <class V>
inline V blendCorners(V a, V b, V c, V d, V ax, V ay) {
  const V top = a + ax * (b - a);
  const V bottom = c + ax * (d - c);
  return top + ay * (bottom - top);
}

/// Whether bytePairCorners exists for V: 8-bit blocks loaded as byte pairs (SSE2, NEON).
template <class V>
inline constexpr bool kHasBytePairCorners = false;

/// The bytes p[0], p[1] as one 16-bit word, p[0] in the low byte (one 16-bit load on a
/// little-endian target; the kernels below take the low byte as the left pixel).
inline std::uint16_t bytePair(const std::uint8_t* p) {
  return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
}

#if defined(LDSM_SIMD_SSE)
template <>
inline constexpr bool kHasBytePairCorners<Vec4Sse> = true;
/// The corners of four 8-bit blocks whose right neighbour is the next byte: each block's byte
/// pairs (p00 p10) and (p01 p11) loaded as 16-bit words into one vector and widened into the
/// lanes' integers at once, instead of sixteen byte loads, conversions and lane inserts.
inline void bytePairCorners(const std::uint8_t* const* blocks, std::ptrdiff_t dy1, Vec4Sse& a,
                            Vec4Sse& b, Vec4Sse& c, Vec4Sse& d) {
  __m128i t = _mm_cvtsi32_si128(bytePair(blocks[0]));
  t = _mm_insert_epi16(t, bytePair(blocks[1]), 1);
  t = _mm_insert_epi16(t, bytePair(blocks[2]), 2);
  t = _mm_insert_epi16(t, bytePair(blocks[3]), 3);
  t = _mm_insert_epi16(t, bytePair(blocks[0] + dy1), 4);
  t = _mm_insert_epi16(t, bytePair(blocks[1] + dy1), 5);
  t = _mm_insert_epi16(t, bytePair(blocks[2] + dy1), 6);
  t = _mm_insert_epi16(t, bytePair(blocks[3] + dy1), 7);
  const __m128i zero = _mm_setzero_si128();
  const __m128i upper = _mm_unpacklo_epi8(t, zero);  // lane k: p00 | p10 << 16 of block k
  const __m128i lower = _mm_unpackhi_epi8(t, zero);  // lane k: p01 | p11 << 16
  const __m128i low16 = _mm_set1_epi32(0xFFFF);
  a.n = _mm_cvtepi32_ps(_mm_and_si128(upper, low16));
  b.n = _mm_cvtepi32_ps(_mm_srli_epi32(upper, 16));
  c.n = _mm_cvtepi32_ps(_mm_and_si128(lower, low16));
  d.n = _mm_cvtepi32_ps(_mm_srli_epi32(lower, 16));
}
#elif defined(LDSM_SIMD_NEON)
template <>
inline constexpr bool kHasBytePairCorners<Vec4Neon> = true;
/// The same on NEON: the byte pairs as 16-bit lanes of one vector, widened, the upper and the
/// lower row's pixels separated by an unzip.
inline void bytePairCorners(const std::uint8_t* const* blocks, std::ptrdiff_t dy1, Vec4Neon& a,
                            Vec4Neon& b, Vec4Neon& c, Vec4Neon& d) {
  uint16x8_t t = vdupq_n_u16(bytePair(blocks[0]));
  t = vsetq_lane_u16(bytePair(blocks[1]), t, 1);
  t = vsetq_lane_u16(bytePair(blocks[2]), t, 2);
  t = vsetq_lane_u16(bytePair(blocks[3]), t, 3);
  t = vsetq_lane_u16(bytePair(blocks[0] + dy1), t, 4);
  t = vsetq_lane_u16(bytePair(blocks[1] + dy1), t, 5);
  t = vsetq_lane_u16(bytePair(blocks[2] + dy1), t, 6);
  t = vsetq_lane_u16(bytePair(blocks[3] + dy1), t, 7);
  const uint8x16_t bytes = vreinterpretq_u8_u16(t);
  // upper: p00 p10 of blocks 0..3 interleaved; lower: p01 p11.
  const uint16x8_t upper = vmovl_u8(vget_low_u8(bytes));
  const uint16x8_t lower = vmovl_u8(vget_high_u8(bytes));
  const uint16x8x2_t split = vuzpq_u16(upper, lower);  // [0]: p00 x4, p01 x4; [1]: p10, p11
  a.n = vcvtq_f32_u32(vmovl_u16(vget_low_u16(split.val[0])));
  c.n = vcvtq_f32_u32(vmovl_u16(vget_high_u16(split.val[0])));
  b.n = vcvtq_f32_u32(vmovl_u16(vget_low_u16(split.val[1])));
  d.n = vcvtq_f32_u32(vmovl_u16(vget_high_u16(split.val[1])));
}
#endif

/// Bilinear blend of the 2x2 blocks at blocks[0..3] (dx1, dy1 the offsets of the right and the
/// lower neighbour) with weights ax (per pixel) and ay (blendCorners). The corners of 8-bit
/// blocks come as byte pairs where V has them (the same values: bytes are exact in float, so
/// bit-identical); otherwise, and for an input one pixel wide (no right neighbour), lane by lane
/// from registers (V::setLanes), not through an array: a vector load of it cannot take its value
/// from the four scalar stores and waits until they are written.
template <class V, typename T>
inline V blendBlocks(const T* const* blocks, std::ptrdiff_t dx1, std::ptrdiff_t dy1, V ax, V ay) {
  if constexpr (std::is_same_v<T, std::uint8_t> && kHasBytePairCorners<V>) {
    if (dx1 == 1) {
      V a, b, c, d;
      bytePairCorners(blocks, dy1, a, b, c, d);
      return blendCorners(a, b, c, d, ax, ay);
    }
  }
  const auto lanes = [&](std::ptrdiff_t o) {
    return V::setLanes(static_cast<float>(blocks[0][o]), static_cast<float>(blocks[1][o]),
                       static_cast<float>(blocks[2][o]), static_cast<float>(blocks[3][o]));
  };
  return blendCorners(lanes(0), lanes(dx1), lanes(dy1), lanes(dy1 + dx1), ax, ay);
}

}  // namespace detail

/// remap of `width` output pixels (see above); map values are >= 0 or exactly -1 (no input).
template <class V, typename T>
inline void remapRow(const RemapInput<T>& in, const float* map_x, const float* map_y, int width,
                     float invalid, float* out) {
  const int max_x0 = std::max(in.width - 2, 0), max_y0 = std::max(in.height - 2, 0);
  const std::ptrdiff_t dx1 = in.width > 1 ? 1 : 0;
  const std::ptrdiff_t dy1 = in.height > 1 ? in.stride : 0;
  const V zero = V::zero();
  const V x_max = V::set1(static_cast<float>(max_x0));
  const V y_max = V::set1(static_cast<float>(max_y0));
  const V bad = V::set1(invalid);
  int u = 0;
  for (; u + 4 <= width; u += 4) {
    const V x = V::loadu(map_x + u), y = V::loadu(map_y + u);
    const typename V::Mask valid = x >= zero;
    // Pixels without input read the block at (0, 0) and are replaced afterwards.
    const V xv = select(valid, x, zero), yv = select(valid, y, zero);
    alignas(16) std::int32_t ix[4], iy[4];
    // The truncation is the floor (>= 0) and exact in float, so the clamp in float equals
    // std::min on the integers; truncating the clamped values again gives their integers.
    V x0 = truncate(xv, ix), y0 = truncate(yv, iy);
    x0 = select(x0 > x_max, x_max, x0);
    y0 = select(y0 > y_max, y_max, y0);
    truncate(x0, ix);
    truncate(y0, iy);
    const T* blocks[4];
    for (int k = 0; k < 4; ++k) blocks[k] = in.row(iy[k]) + ix[k];
    select(valid, detail::blendBlocks<V>(blocks, dx1, dy1, x - x0, y - y0), bad).storeu(out + u);
  }
  reference::remapRow(in, map_x + u, map_y + u, width - u, invalid, out + u);
}

/// A separable table in the form the separable row remap takes: per output column the clamped
/// left input column x0 and the weight ax = x - x0 (-1: the column sees no input; x0 is then 0),
/// exactly as remapRow computes them from the column's x.
struct SeparableColumns {
  std::vector<std::int32_t> x0;
  std::vector<float> ax;
};

/// The clamped top-left input pixel index and weight of input coordinate `c` in a dimension of
/// `size` pixels, as remapRow computes them.
inline void clampedCell(float c, int size, std::int32_t& c0, float& a) {
  c0 = std::min(static_cast<int>(c), std::max(size - 2, 0));
  a = c - static_cast<float>(c0);
}

/// SeparableColumns of the input x of each output column (-1: none) for an input `width` wide.
inline SeparableColumns separableColumns(const std::vector<float>& column_x, int width) {
  SeparableColumns out;
  out.x0.assign(column_x.size(), 0);
  out.ax.assign(column_x.size(), -1.f);
  for (std::size_t u = 0; u < column_x.size(); ++u)
    if (column_x[u] >= 0.f) clampedCell(column_x[u], width, out.x0[u], out.ax[u]);
  return out;
}

namespace reference {

/// remapRow of an output row whose pixels all sample input row y (cell y0, weight ay from
/// clampedCell) at the columns of `cols`: the same arithmetic per pixel.
template <typename T>
inline void remapSeparableRow(const RemapInput<T>& in, const std::int32_t* x0, const float* ax,
                              std::int32_t y0, float ay, int width, float invalid, float* out) {
  const std::ptrdiff_t dx1 = in.width > 1 ? 1 : 0;
  const std::ptrdiff_t dy1 = in.height > 1 ? in.stride : 0;
  const T* row = in.row(y0);
  for (int u = 0; u < width; ++u) {
    if (ax[u] < 0.0f) {
      out[u] = invalid;
      continue;
    }
    const T* p = row + x0[u];
    const float top = static_cast<float>(p[0]) + ax[u] * (static_cast<float>(p[dx1]) - p[0]);
    const float bottom =
        static_cast<float>(p[dy1]) + ax[u] * (static_cast<float>(p[dy1 + dx1]) - p[dy1]);
    out[u] = top + ay * (bottom - top);
  }
}

}  // namespace reference

/// The same four output pixels per vector: the weights and the invalid columns from the
/// precomputed columns, the 2x2 blocks loaded per pixel. Bit-identical to the reference (and so
/// to remapRow with the row's y repeated).
template <class V, typename T>
inline void remapSeparableRow(const RemapInput<T>& in, const std::int32_t* x0, const float* ax,
                              std::int32_t y0, float ay, int width, float invalid, float* out) {
  const std::ptrdiff_t dx1 = in.width > 1 ? 1 : 0;
  const std::ptrdiff_t dy1 = in.height > 1 ? in.stride : 0;
  const T* row = in.row(y0);
  const V zero = V::zero();
  const V bad = V::set1(invalid);
  const V vay = V::set1(ay);
  int u = 0;
  for (; u + 4 <= width; u += 4) {
    const V a = V::loadu(ax + u);
    const T* blocks[4];
    for (int k = 0; k < 4; ++k) blocks[k] = row + x0[u + k];
    select(a >= zero, detail::blendBlocks<V>(blocks, dx1, dy1, a, vay), bad).storeu(out + u);
  }
  reference::remapSeparableRow(in, x0 + u, ax + u, y0, ay, width - u, invalid, out + u);
}

}  // namespace simd
}  // namespace ldsm
