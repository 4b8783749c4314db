// Bilinear interpolation of float images and of packed (intensity, dx, dy) pyramid levels, for
// per-pixel use in tracking: inline, no checks beyond a debug assert; call isInsideForBilinear()
// first. Pixel (x, y) has its centre at integer coordinates.
#pragma once

#include <cassert>

#include "image/gradient_pixel.h"
#include "ldsm/image.h"

namespace ldsm {

/// True when (x, y) lies at least `margin` pixels inside the region where bilinear interpolation
/// reads only valid pixels: margin <= x < width - 1 - margin, same for y. False for NaN.
inline bool isInsideForBilinear(float x, float y, int width, int height, float margin = 0.f) {
  return x >= margin && y >= margin && x < static_cast<float>(width - 1) - margin &&
         y < static_cast<float>(height - 1) - margin;
}

template <typename T>
inline bool isInsideForBilinear(const ImageView<T>& image, float x, float y, float margin = 0.f) {
  return isInsideForBilinear(x, y, image.width, image.height, margin);
}

namespace detail {

/// Bilinear interpolation of value(pixel) at (x, y), in the order of operations both float
/// interpolations below share (so that they agree bit for bit on the same intensities).
template <typename T, typename Value>
inline float bilinearOf(ImageView<const T> image, float x, float y, Value value) {
  assert(isInsideForBilinear(image, x, y));
  const int ix = static_cast<int>(x);
  const int iy = static_cast<int>(y);
  const float fx = x - static_cast<float>(ix);
  const float fy = y - static_cast<float>(iy);
  const T* p = image.data + iy * image.stride + ix;
  const T* q = p + image.stride;
  const float p0 = value(p[0]), p1 = value(p[1]), q0 = value(q[0]), q1 = value(q[1]);
  const float top = p0 + fx * (p1 - p0);
  const float bottom = q0 + fx * (q1 - q0);
  return top + fy * (bottom - top);
}

}  // namespace detail

/// Bilinear interpolation of a float image at (x, y). Requires isInsideForBilinear(image, x, y).
inline float interpolateBilinear(ImageView<const float> image, float x, float y) {
  return detail::bilinearOf(image, x, y, [](float v) { return v; });
}

/// Bilinear interpolation of the intensity of a packed level at (x, y), with the arithmetic of the
/// float-image interpolateBilinear() (the same value as on a plane of the intensities). Requires
/// isInsideForBilinear(image, x, y).
inline float interpolateIntensity(ImageView<const GradientPixel> image, float x, float y) {
  return detail::bilinearOf(image, x, y, [](const GradientPixel& g) { return g.intensity; });
}

namespace detail {

/// Bilinear intensity, dx and dy at (x, y) of the packed pixels at(ix, iy) gives (by value or
/// reference), weights first: the one formulation of every packed plane's interpolation.
template <typename At>
inline GradientPixel bilinearPacked(float x, float y, At at) {
  const int ix = static_cast<int>(x);
  const int iy = static_cast<int>(y);
  const float fx = x - static_cast<float>(ix);
  const float fy = y - static_cast<float>(iy);
  const float w00 = (1.f - fx) * (1.f - fy);
  const float w10 = fx * (1.f - fy);
  const float w01 = (1.f - fx) * fy;
  const float w11 = fx * fy;
  const GradientPixel p0 = at(ix, iy), p1 = at(ix + 1, iy);
  const GradientPixel q0 = at(ix, iy + 1), q1 = at(ix + 1, iy + 1);
  return {w00 * p0.intensity + w10 * p1.intensity + w01 * q0.intensity + w11 * q1.intensity,
          w00 * p0.dx + w10 * p1.dx + w01 * q0.dx + w11 * q1.dx,
          w00 * p0.dy + w10 * p1.dy + w01 * q0.dy + w11 * q1.dy};
}

}  // namespace detail

/// Bilinear interpolation of intensity, dx and dy of a packed level at (x, y). Requires
/// isInsideForBilinear(image, x, y).
inline GradientPixel interpolateBilinear(ImageView<const GradientPixel> image, float x, float y) {
  assert(isInsideForBilinear(image, x, y));
  return detail::bilinearPacked(x, y, [&image](int u, int v) { return image(u, v); });
}

}  // namespace ldsm
