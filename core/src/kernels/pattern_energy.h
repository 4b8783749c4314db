// The immature points' depth search: the weighted Huber energy of the 8-pixel pattern at one
// position of the epipolar line, intensities only (bilinear), computed at every pixel step of the
// line (up to max_search_length steps per point and frame, the bulk of the tracing):
//   E(x, y) = sum_k w_k * (|r_k| <= th ? r_k^2 : th (2 |r_k| - th)),
//   r_k = I(x + ox_k, y + oy_k) - expected_k.
// patternEnergy<V> evaluates the pattern as two 4-lane halves (positions, bilinear weights and
// the Huber terms in SIMD; the four corner intensities of each pixel are plain loads: SSE2 and
// NEON have no gather) and sums the eight terms in pixel order, so that it equals the plain
// per-pixel formulation reference::patternEnergy exactly (the search's best match and its
// ambiguity do not depend on the instruction set).
#pragma once

#include <cstddef>
#include <cstdint>

#include "image/gradient_pixel.h"
#include "ldsm/image.h"
#include "math/simd/vec4f.h"
#include "model/residual_pattern.h"

namespace ldsm {
namespace simd {

static_assert(kPatternSize == 8, "the kernel processes the pattern as two 4-lane halves");

/// The pattern as it is compared along one epipolar line: offsets in target pixels, expected
/// target intensities (the host's through the affine transfer) and weights.
struct PatternEnergyParams {
  ImageView<const GradientPixel> image;  ///< target level 0
  alignas(16) float ox[kPatternSize];
  alignas(16) float oy[kPatternSize];
  alignas(16) float expected[kPatternSize];
  alignas(16) float weights[kPatternSize];
  float huber = 9.f;
};

/// Requires every pattern pixel (x + ox_k, y + oy_k) inside the bilinear region of the image.
template <class V>
inline float patternEnergy(const PatternEnergyParams& m, float x, float y) {
  const V th = V::set1(m.huber);
  const V two = V::set1(2.f);
  alignas(16) float terms[kPatternSize];
  LDSM_SIMD_UNROLL
  for (int h = 0; h < 2; ++h) {
    const V px = V::set1(x) + V::load(m.ox + 4 * h);
    const V py = V::set1(y) + V::load(m.oy + 4 * h);
    alignas(16) std::int32_t ix[4];
    alignas(16) std::int32_t iy[4];
    const V fx = px - truncate(px, ix);  // positive coordinates: truncation is the floor
    const V fy = py - truncate(py, iy);
    // The corners go into lanes from registers (V::setLanes): written to arrays and loaded as
    // vectors, each load could not take its value from the four stores and waited until they
    // were written (a call at random positions: 47 -> 28 ns on an AMD EPYC; in the tracing,
    // whose neighbouring calls overlap, much less).
    const GradientPixel* p[4];  // the top-left corner of each lane's 2x2 block
    for (int k = 0; k < 4; ++k)
      p[k] = m.image.data + static_cast<std::ptrdiff_t>(iy[k]) * m.image.stride + ix[k];
    const std::ptrdiff_t s = m.image.stride;  // the corner below
    const V tl =
        V::setLanes(p[0][0].intensity, p[1][0].intensity, p[2][0].intensity, p[3][0].intensity);
    const V tr =
        V::setLanes(p[0][1].intensity, p[1][1].intensity, p[2][1].intensity, p[3][1].intensity);
    const V bl =
        V::setLanes(p[0][s].intensity, p[1][s].intensity, p[2][s].intensity, p[3][s].intensity);
    const V br = V::setLanes(p[0][s + 1].intensity, p[1][s + 1].intensity, p[2][s + 1].intensity,
                             p[3][s + 1].intensity);
    const V top = tl + fx * (tr - tl);
    const V bottom = bl + fx * (br - bl);
    const V r = top + fy * (bottom - top) - V::load(m.expected + 4 * h);
    const V a = absolute(r);
    (V::load(m.weights + 4 * h) * select(a > th, th * (two * a - th), r * r)).store(terms + 4 * h);
  }
  float e = 0.f;
  for (int k = 0; k < kPatternSize; ++k) e += terms[k];
  return e;
}

namespace reference {

/// The plain per-pixel formulation of patternEnergy.
inline float patternEnergy(const PatternEnergyParams& m, float x, float y) {
  float e = 0.f;
  for (int k = 0; k < kPatternSize; ++k) {
    const float px = x + m.ox[k], py = y + m.oy[k];
    const int ix = static_cast<int>(px);
    const int iy = static_cast<int>(py);
    const float fx = px - static_cast<float>(ix);
    const float fy = py - static_cast<float>(iy);
    const GradientPixel* p = m.image.data + static_cast<std::ptrdiff_t>(iy) * m.image.stride + ix;
    const GradientPixel* q = p + m.image.stride;
    const float top = p[0].intensity + fx * (p[1].intensity - p[0].intensity);
    const float bottom = q[0].intensity + fx * (q[1].intensity - q[0].intensity);
    const float r = top + fy * (bottom - top) - m.expected[k];
    const float a = r < 0.f ? -r : r;
    e += m.weights[k] * (a <= m.huber ? r * r : m.huber * (2.f * a - m.huber));
  }
  return e;
}

}  // namespace reference
}  // namespace simd
}  // namespace ldsm
