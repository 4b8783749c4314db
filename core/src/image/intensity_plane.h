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

/// A level-0 intensity plane as readers take it.
struct IntensityPlaneView {
  ImageView<const float> pixels;

  int width() const { return pixels.width; }
  int height() const { return pixels.height; }
  /// The packed plane's pixel (x, y).
  GradientPixel at(int x, int y) const {
    const float* row = pixels.row(y);
    const bool inner = x > 0 && y > 0 && x < pixels.width - 1 && y < pixels.height - 1;
    if (!inner) return {row[x], 0.f, 0.f};
    return {row[x], 0.5f * (row[x + 1] - row[x - 1]),
            0.5f * (pixels.row(y + 1)[x] - pixels.row(y - 1)[x])};
  }
};

/// Bilinear interpolation of intensity, dx and dy at (x, y), bit for bit that of
/// interpolateBilinear() on the packed plane. Requires isInsideForBilinear(x, y, width, height).
inline GradientPixel interpolateBilinear(const IntensityPlaneView& image, float x, float y) {
  assert(isInsideForBilinear(x, y, image.width(), image.height()));
  return detail::bilinearPacked(x, y, [&image](int u, int v) { return image.at(u, v); });
}

}  // namespace ldsm
