// First half of a photometric residual's evaluation over the 8-pixel pattern: project the pattern
// into the target (3x3 K R K^-1 and K t at the current estimate), sample the target's packed
// (intensity, dx, dy) bilinearly, and form per pixel
//   r = I_t - scale * I_h - offset,
//   gw = (sqrt(c^2 / (c^2 + |grad I_t|^2)) + host gradient weight) / 2,
//   Huber weight hw = min(1, th / |r|),  w = gw^2 hw,
//   energy = gw^2 * (|r| < th ? r^2 : 2 th |r| - th^2),
// as a struct of arrays over the pattern. samplePattern<V> is the SIMD kernel (V from vec4f.h:
// two 4-lane halves, one bilinear lookup per pixel as two 4-float loads per image row);
// reference::samplePattern is the plain per-pixel formulation it must agree with. The target is
// the newest keyframe's packed float plane, or a compacted keyframe's intensities alone, in float
// (image/intensity_plane.h) or 16 bits (image/compact_plane.h): the kernel then loads each pattern
// pixel's 4x4 neighbourhood and makes the gradients with the pyramid's arithmetic (the packed
// plane's bits), a 16-bit plane in units of its step, scaled once per pattern half.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "image/compact_plane.h"
#include "image/gradient_pixel.h"
#include "image/intensity_plane.h"
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
  ImageView<const GradientPixel> image;  ///< target level 0 (unless another plane is set)
  IntensityPlaneView intensity;          ///< the target's compacted level 0, when set
  CompactPlaneView compact;              ///< the target's 16-bit level 0, when set
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

/// (intensity, dx, dy) of four pattern pixels as rows (lane k: pixel k, top-left corner
/// (x[k], y[k]), weights lane k of w00..w11) on a packed float plane: one bilinearPixel per
/// pixel, transposed.
template <class V>
[[gnu::always_inline]] inline void bilinearRows(const ImageView<const GradientPixel>& image,
                                                const std::int32_t* x, const std::int32_t* y, V w00,
                                                V w10, V w01, V w11, V& I, V& gx, V& gy) {
  I = bilinearPixel<V, 0>(image, x[0], y[0], w00, w10, w01, w11);
  gx = bilinearPixel<V, 1>(image, x[1], y[1], w00, w10, w01, w11);
  gy = bilinearPixel<V, 2>(image, x[2], y[2], w00, w10, w01, w11);
  V unused = bilinearPixel<V, 3>(image, x[3], y[3], w00, w10, w01, w11);
  transpose4(I, gx, gy, unused);
}

/// Four values of a row of intensities as a vector (float or 16-bit plane).
template <class V>
inline V loadRow(const float* p) {
  return V::loadu(p);
}
template <class V>
inline V loadRow(const std::int16_t* p) {
  return V::loadInt16(p);
}

/// The same on a plane of intensities alone (`data`, `stride` elements per row): each pixel's
/// 4x4 neighbourhood rows (columns x-1..x+2 of rows y-1..y+2) transposed, so that lane k of row j
/// of A, B, C, D holds I(x[k] - 1 + j) on rows y[k] - 1, y[k], y[k] + 1, y[k] + 2; the four
/// corners' gradients are made with the pyramid's arithmetic (0.5 (right - left),
/// 0.5 (below - above)) and blended as bilinearPixel blends the packed plane's values
/// ((p00 w00 + p01 w01) + (p10 w10 + p11 w11)): the same bits. Needs 1 <= x, x + 2 <= width - 1
/// and the same for y (a margin of at least 1).
template <class V, class T>
[[gnu::always_inline]] inline void bilinearFromIntensityRows(const T* data, std::ptrdiff_t stride,
                                                             const std::int32_t* x,
                                                             const std::int32_t* y, V w00, V w10,
                                                             V w01, V w11, V& I, V& gx, V& gy) {
  V A[4], B[4], C[4], D[4];
  LDSM_SIMD_UNROLL
  for (int k = 0; k < 4; ++k) {
    const T* b = data + static_cast<std::ptrdiff_t>(y[k]) * stride + (x[k] - 1);
    A[k] = loadRow<V>(b - stride);
    B[k] = loadRow<V>(b);
    C[k] = loadRow<V>(b + stride);
    D[k] = loadRow<V>(b + 2 * stride);
  }
  transpose4(A[0], A[1], A[2], A[3]);
  transpose4(B[0], B[1], B[2], B[3]);
  transpose4(C[0], C[1], C[2], C[3]);
  transpose4(D[0], D[1], D[2], D[3]);
  const V half = V::set1(0.5f);
  I = (B[1] * w00 + C[1] * w01) + (B[2] * w10 + C[2] * w11);
  gx = (half * (B[2] - B[0]) * w00 + half * (C[2] - C[0]) * w01) +
       (half * (B[3] - B[1]) * w10 + half * (C[3] - C[1]) * w11);
  gy = (half * (C[1] - A[1]) * w00 + half * (D[1] - B[1]) * w01) +
       (half * (C[2] - A[2]) * w10 + half * (D[2] - B[2]) * w11);
}

/// On a plane of intensities alone: float (IntensityPlaneView) or 16 bits (CompactPlaneView, in
/// units of its step: the caller scales by it, a power of two, so the result is that of the float
/// intensity plane of the decoded values, bit for bit).
template <class V, class IntensityPlane>
[[gnu::always_inline]] inline void bilinearRows(const IntensityPlane& image, const std::int32_t* x,
                                                const std::int32_t* y, V w00, V w10, V w01, V w11,
                                                V& I, V& gx, V& gy) {
  bilinearFromIntensityRows<V>(image.pixels.data, image.pixels.stride, x, y, w00, w10, w01, w11, I,
                               gx, gy);
}

/// The factor bilinearPixel's results on `img` are in: 1 for float planes, the step of compact
/// ones.
inline float planeUnit(const ImageView<const GradientPixel>&) {
  return 1.f;
}
inline float planeUnit(const CompactPlaneView& img) {
  return img.step;
}
inline float planeUnit(const IntensityPlaneView&) {
  return 1.f;
}
/// The least margin a plane's kernel reads within (bilinearRows on a plane of intensities alone
/// reads one pixel around the 2x2 block).
inline float planeMargin(const ImageView<const GradientPixel>&, float margin) {
  return margin;
}
inline float planeMargin(const CompactPlaneView&, float margin) {
  return margin < 1.f ? 1.f : margin;
}
inline float planeMargin(const IntensityPlaneView&, float margin) {
  return margin < 1.f ? 1.f : margin;
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
inline int planeWidth(const IntensityPlaneView& img) {
  return img.width();
}
inline int planeHeight(const IntensityPlaneView& img) {
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
  if (p.intensity.pixels.data != nullptr)
    return detail::samplePatternIn<V>(p.intensity, p, pw, pt, out);
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
  const float margin = planeMargin(image, pw.margin);
  const V lo = V::set1(margin);
  const V x_hi = V::set1(static_cast<float>(planeWidth(image) - 1) - margin);
  const V y_hi = V::set1(static_cast<float>(planeHeight(image) - 1) - margin);
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
    V I, gx, gy;
    bilinearRows<V>(image, ix + o, iy + o, w00, w10, w01, w11, I, gx, gy);
    if constexpr (std::is_same_v<Plane, CompactPlaneView>) {
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
    Level0View target;
    target.full = p.image;
    target.intensity = p.intensity;
    target.compact = p.compact;
    int w = p.image.width, h = p.image.height;
    float margin = pw.margin;
    if (target.isCompact()) {
      w = p.compact.width();
      h = p.compact.height();
      margin = detail::planeMargin(p.compact, pw.margin);
    } else if (target.isIntensity()) {
      w = p.intensity.width();
      h = p.intensity.height();
      margin = detail::planeMargin(p.intensity, pw.margin);
    }
    if (!(qz > 0.f) || !isInsideForBilinear(x, y, w, h, margin)) return false;
    const GradientPixel g = interpolateBilinear(target, x, y);
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
