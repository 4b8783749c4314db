// The level-0 intensities of a keyframe that is only the target of residuals, without the stored
// gradients: 4 instead of 12 bytes per pixel. A pixel's (intensity, dx, dy) is made again from
// its neighbours with the arithmetic of the pyramid's gradient rows (image/gradient_row.h):
//   dx = 0.5 (I(x+1) - I(x-1)),  dy = 0.5 (I(x, y+1) - I(x, y-1)),  zero on the one-pixel border,
// so every value read equals the packed plane's bit for bit, and so does any interpolation of them.
#pragma once

#include <cassert>

#include "image/gradient_pixel.h"
#include "image/interpolation.h"
#include "ldsm/image.h"

namespace ldsm {

/// The packed plane's pixel (x, y) of a width x height plane of intensities `I(x, y)`: its
/// intensity and central differences, zero on the one-pixel border.
template <class Intensity>
inline GradientPixel centralDifferencePixel(int x, int y, int width, int height, Intensity I) {
  const bool inner = x > 0 && y > 0 && x < width - 1 && y < height - 1;
  if (!inner) return {I(x, y), 0.f, 0.f};
  return {I(x, y), 0.5f * (I(x + 1, y) - I(x - 1, y)), 0.5f * (I(x, y + 1) - I(x, y - 1))};
}

/// A level-0 intensity plane as readers take it.
struct IntensityPlaneView {
  ImageView<const float> pixels;

  int width() const { return pixels.width; }
  int height() const { return pixels.height; }
  /// The packed plane's pixel (x, y).
  GradientPixel at(int x, int y) const {
    return centralDifferencePixel(x, y, width(), height(),
                                  [this](int u, int v) { return pixels(u, v); });
  }
};

/// Bilinear interpolation of intensity, dx and dy at (x, y), bit for bit that of
/// interpolateBilinear() on the packed plane. Requires isInsideForBilinear(x, y, width, height).
inline GradientPixel interpolateBilinear(const IntensityPlaneView& image, float x, float y) {
  assert(isInsideForBilinear(x, y, image.width(), image.height()));
  return detail::bilinearPacked(x, y, [&image](int u, int v) { return image.at(u, v); });
}

}  // namespace ldsm
