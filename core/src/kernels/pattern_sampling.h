// First half of a photometric residual's evaluation over the 8-pixel pattern: project the pattern
// into the target (3x3 K R K^-1 and K t at the current estimate), sample the target's packed
// (intensity, dx, dy) bilinearly, and form per pixel
//   r = I_t - scale * I_h - offset,
//   gw = (sqrt(c^2 / (c^2 + |grad I_t|^2)) + host gradient weight) / 2,
//   Huber weight hw = min(1, th / |r|),  w = gw^2 hw,
//   energy = gw^2 * (|r| < th ? r^2 : 2 th |r| - th^2),
// as a struct of arrays over the pattern. samplePattern<V> is the SIMD kernel (V from vec4f.h:
// two 4-lane halves, one bilinear lookup per pixel as two 4-float loads per image row);
// reference::samplePattern is the plain per-pixel formulation it must agree with. The target is a
// float plane or a compacted keyframe's 16-bit one (image/compact_plane.h), which the kernel
// interpolates in units of the plane's step and scales once per pattern half.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "image/compact_plane.h"
#include "image/gradient_pixel.h"
#include "image/interpolation.h"
#include "ldsm/image.h"
#include "math/simd/vec4f.h"
#include "model/residual_pattern.h"

namespace ldsm {
namespace simd {

static_assert(kPatternSize == 8, "the kernels process the pattern as two 4-lane halves");

/// The pattern offsets as a struct of arrays.
struct alignas(16) PatternOffsetsSoA {
  float dx[kPatternSize];
  float dy[kPatternSize];
};
constexpr PatternOffsetsSoA makePatternOffsetsSoA() {
  PatternOffsetsSoA o{};
  for (int k = 0; k < kPatternSize; ++k) {
    o.dx[k] = static_cast<float>(kPatternOffsets[k][0]);
    o.dy[k] = static_cast<float>(kPatternOffsets[k][1]);
  }
  return o;
}
inline constexpr PatternOffsetsSoA kPatternOffsetsSoA = makePatternOffsetsSoA();

/// What the residuals of one (host, target) pair share.
struct PatternSamplingParams {
  float KRKi[9] = {};  ///< K R_th K^-1, column-major
  float Kt[3] = {};    ///< K t_th
  float scale = 1.f;   ///< affine transfer host -> target: I_t ~ scale * I_h + offset
  float offset = 0.f;
  ImageView<const GradientPixel> image;  ///< target level 0 (unless `compact` is set)
  CompactPlaneView compact;              ///< the target's compacted level 0, when set
};

/// The residual settings the sampling needs.
struct PatternWeighting {
  float gradient_c2 = 2500.f;  ///< c^2 of the gradient weight
  float huber = 9.f;           ///< Huber threshold (grey levels)
  float margin = 2.f;          ///< every pattern pixel keeps this far inside the bilinear region
};

/// The host side of one point.
struct PatternPoint {
  float u = 0.f, v = 0.f;  ///< host pixel
  float idepth = 1.f;
  const float* colors = nullptr;        ///< kPatternSize host intensities
  const float* grad_weights = nullptr;  ///< kPatternSize host gradient weights (square roots)
  /// Added to every projected pattern pixel (the radial correction's shift at the centre).
  float shift_x = 0.f, shift_y = 0.f;
};

/// Per pattern pixel: target gradient, residual and normal-equation weight; and the energy.
struct alignas(16) PatternSamples {
  float gx[kPatternSize];
  float gy[kPatternSize];
  float r[kPatternSize];
  float w[kPatternSize];  ///< gw^2 * Huber weight
  float energy = 0.f;     ///< sum of the pixels' weighted Huber energies
};

namespace detail {

/// Bilinear (intensity, dx, dy, -) of the pixel at integer corner (x, y), weights from lane K.
/// Reads only the 2x2 block's 12 floats: the right column is loaded one float early and shifted.
template <class V, int K>
inline V bilinearPixel(const ImageView<const GradientPixel>& img, std::int32_t x, std::int32_t y,
                       V w00, V w10, V w01, V w11) {
  const float* p = &img.data[static_cast<std::ptrdiff_t>(y) * img.stride + x].intensity;
  const float* q = p + 3 * img.stride;
  const V left = V::loadu(p) * broadcast<K>(w00) + V::loadu(q) * broadcast<K>(w01);
  const V right = V::loadu(p + 2) * broadcast<K>(w10) + V::loadu(q + 2) * broadcast<K>(w11);
  return left + shiftDown1(right);
}

/// The same on a compact plane, in units of its step: one 4-lane load per pixel (its three
/// values and the next pixel's intensity), summed in the float version's order.
template <class V, int K>
inline V bilinearPixel(const CompactPlaneView& img, std::int32_t x, std::int32_t y, V w00, V w10,
                       V w01, V w11) {
  const std::int16_t* p =
      &img.pixels.data[static_cast<std::ptrdiff_t>(y) * img.pixels.stride + x].intensity;
  const std::int16_t* q = p + 3 * img.pixels.stride;
  const V left = V::loadInt16(p) * broadcast<K>(w00) + V::loadInt16(q) * broadcast<K>(w01);
  const V right = V::loadInt16(p + 3) * broadcast<K>(w10) + V::loadInt16(q + 3) * broadcast<K>(w11);
  return left + right;
}

/// The factor bilinearPixel's results on `img` are in: 1 for float planes, the step of compact
/// ones.
inline float planeUnit(const ImageView<const GradientPixel>&) {
  return 1.f;
}
inline float planeUnit(const CompactPlaneView& img) {
  return img.step;
}

inline int planeWidth(const ImageView<const GradientPixel>& img) {
  return img.width;
}
inline int planeHeight(const ImageView<const GradientPixel>& img) {
  return img.height;
}
inline int planeWidth(const CompactPlaneView& img) {
  return img.width();
}
inline int planeHeight(const CompactPlaneView& img) {
  return img.height();
}

template <class V, class Plane>
[[gnu::always_inline]] inline bool samplePatternIn(const Plane& image,
                                                   const PatternSamplingParams& p,
                                                   const PatternWeighting& pw,
                                                   const PatternPoint& pt, PatternSamples& out);

}  // namespace detail

/// Projects and samples the pattern of `pt` in the pair's target. Returns false (leaving `out`
/// unspecified) when a pattern pixel is behind the camera, outside the image minus the margin,
/// or not finite.
template <class V>
[[gnu::always_inline]] inline bool samplePattern(const PatternSamplingParams& p,
                                                 const PatternWeighting& pw, const PatternPoint& pt,
                                                 PatternSamples& out) {
  return p.compact.pixels.data != nullptr ? detail::samplePatternIn<V>(p.compact, p, pw, pt, out)
                                          : detail::samplePatternIn<V>(p.image, p, pw, pt, out);
}

template <class V, class Plane>
[[gnu::always_inline]] inline bool detail::samplePatternIn(const Plane& image,
                                                           const PatternSamplingParams& p,
                                                           const PatternWeighting& pw,
                                                           const PatternPoint& pt,
                                                           PatternSamples& out) {
  const float* K = p.KRKi;
  const float d = pt.idepth;
  const V bx = V::set1(K[0] * pt.u + K[3] * pt.v + K[6] + p.Kt[0] * d);
  const V by = V::set1(K[1] * pt.u + K[4] * pt.v + K[7] + p.Kt[1] * d);
  const V bz = V::set1(K[2] * pt.u + K[5] * pt.v + K[8] + p.Kt[2] * d);
  const V lo = V::set1(pw.margin);
  const V x_hi = V::set1(static_cast<float>(planeWidth(image) - 1) - pw.margin);
  const V y_hi = V::set1(static_cast<float>(planeHeight(image) - 1) - pw.margin);
  const V one = V::set1(1.f);
  alignas(16) std::int32_t ix[kPatternSize];
  alignas(16) std::int32_t iy[kPatternSize];
  V fx[2], fy[2];
  LDSM_SIMD_UNROLL
  for (int h = 0; h < 2; ++h) {
    const V ox = V::load(kPatternOffsetsSoA.dx + 4 * h);
    const V oy = V::load(kPatternOffsetsSoA.dy + 4 * h);
    const V qx = bx + ox * V::set1(K[0]) + oy * V::set1(K[3]);
    const V qy = by + ox * V::set1(K[1]) + oy * V::set1(K[4]);
    const V qz = bz + ox * V::set1(K[2]) + oy * V::set1(K[5]);
    const V x = qx / qz + V::set1(pt.shift_x);
    const V y = qy / qz + V::set1(pt.shift_y);
    // Ordered comparisons: NaN fails them all.
    if (!allOf((qz > V::zero()) & (x >= lo) & (y >= lo) & (x < x_hi) & (y < y_hi))) return false;
    fx[h] = x - truncate(x, ix + 4 * h);  // x >= 0 here, so truncation is the floor
    fy[h] = y - truncate(y, iy + 4 * h);
  }

  const V th = V::set1(pw.huber);
  const V c2 = V::set1(pw.gradient_c2);
  V energy = V::zero();
  LDSM_SIMD_UNROLL
  for (int h = 0; h < 2; ++h) {
    const V w00 = (one - fx[h]) * (one - fy[h]);
    const V w10 = fx[h] * (one - fy[h]);
    const V w01 = (one - fx[h]) * fy[h];
    const V w11 = fx[h] * fy[h];
    const int o = 4 * h;
    // One (intensity, dx, dy, -) vector per pixel, transposed into intensity, dx, dy rows.
    V I = bilinearPixel<V, 0>(image, ix[o], iy[o], w00, w10, w01, w11);
    V gx = bilinearPixel<V, 1>(image, ix[o + 1], iy[o + 1], w00, w10, w01, w11);
    V gy = bilinearPixel<V, 2>(image, ix[o + 2], iy[o + 2], w00, w10, w01, w11);
    V unused = bilinearPixel<V, 3>(image, ix[o + 3], iy[o + 3], w00, w10, w01, w11);
    transpose4(I, gx, gy, unused);
    if constexpr (!std::is_same_v<Plane, ImageView<const GradientPixel>>) {
      const V unit = V::set1(planeUnit(image));
      I = I * unit;
      gx = gx * unit;
      gy = gy * unit;
    }

    const V r = I - V::set1(p.scale) * V::loadu(pt.colors + o) - V::set1(p.offset);
    const V gw_target = squareRoot(c2 / (c2 + gx * gx + gy * gy));
    const V gw = V::set1(0.5f) * (gw_target + V::loadu(pt.grad_weights + o));
    const V gw2 = gw * gw;
    const V ar = absolute(r);
    const typename V::Mask inlier = ar < th;
    energy = energy + gw2 * select(inlier, r * r,
                                   V::set1(2.f * pw.huber) * ar - V::set1(pw.huber * pw.huber));
    const V w = gw2 * select(inlier, one, th / ar);
    gx.store(out.gx + o);
    gy.store(out.gy + o);
    r.store(out.r + o);
    w.store(out.w + o);
  }
  out.energy = horizontalSum(energy);
  return true;
}

namespace reference {

/// The plain per-pixel formulation of samplePattern (same projection arithmetic, so that the
/// two agree to rounding of the sums).
inline bool samplePattern(const PatternSamplingParams& p, const PatternWeighting& pw,
                          const PatternPoint& pt, PatternSamples& out) {
  const float* K = p.KRKi;
  const float th = pw.huber;
  // The centre's projection plus the images of the offsets (as the kernel computes it).
  const float bx = K[0] * pt.u + K[3] * pt.v + K[6] + p.Kt[0] * pt.idepth;
  const float by = K[1] * pt.u + K[4] * pt.v + K[7] + p.Kt[1] * pt.idepth;
  const float bz = K[2] * pt.u + K[5] * pt.v + K[8] + p.Kt[2] * pt.idepth;
  float energy = 0.f;
  for (int k = 0; k < kPatternSize; ++k) {
    const float ox = kPatternOffsetsSoA.dx[k];
    const float oy = kPatternOffsetsSoA.dy[k];
    const float qx = bx + ox * K[0] + oy * K[3];
    const float qy = by + ox * K[1] + oy * K[4];
    const float qz = bz + ox * K[2] + oy * K[5];
    const float x = qx / qz + pt.shift_x;
    const float y = qy / qz + pt.shift_y;
    const bool compact = p.compact.pixels.data != nullptr;
    const int w = compact ? p.compact.width() : p.image.width;
    const int h = compact ? p.compact.height() : p.image.height;
    if (!(qz > 0.f) || !isInsideForBilinear(x, y, w, h, pw.margin)) return false;
    const GradientPixel g =
        compact ? interpolateBilinear(p.compact, x, y) : interpolateBilinear(p.image, x, y);
    const float r = g.intensity - p.scale * pt.colors[k] - p.offset;
    const float gw_target =
        std::sqrt(pw.gradient_c2 / (pw.gradient_c2 + g.dx * g.dx + g.dy * g.dy));
    const float gw = 0.5f * (gw_target + pt.grad_weights[k]);
    const float ar = std::fabs(r);
    const float hw = ar < th ? 1.f : th / ar;
    energy += gw * gw * (ar < th ? r * r : 2.f * th * ar - th * th);
    out.gx[k] = g.dx;
    out.gy[k] = g.dy;
    out.r[k] = r;
    out.w[k] = gw * gw * hw;
  }
  out.energy = energy;
  return true;
}

}  // namespace reference
}  // namespace simd
}  // namespace ldsm
