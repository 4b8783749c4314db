// The level-0 intensities of a keyframe that is only the target of residuals, in 16-bit fixed
// point (window.keyframe_images_16bit): 2 instead of 4 bytes per pixel. Stored values are
// round(value * scale) with scale a power of two, the finest at which the plane's largest
// magnitude fits into int16 (128 for grey levels up to 255: steps of 1/128 grey level), so
// decoding (stored * 2^-k) is exact. A pixel's gradients are made from its decoded neighbours as
// on a float intensity plane (image/intensity_plane.h), so the plane reads exactly as the float
// intensity plane of the rounded values.
#pragma once

#include <cassert>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "image/gradient_pixel.h"
#include "image/intensity_plane.h"
#include "image/interpolation.h"
#include "ldsm/image.h"

namespace ldsm {

/// A compact plane as readers take it: value = stored * step.
struct CompactPlaneView {
  ImageView<const std::int16_t> pixels;
  float step = 0.f;  ///< a power of two

  int width() const { return pixels.width; }
  int height() const { return pixels.height; }
  float intensity(int x, int y) const { return step * static_cast<float>(pixels(x, y)); }
  /// Decoded intensity and the gradients of the decoded values (zero on the one-pixel border).
  GradientPixel at(int x, int y) const {
    return centralDifferencePixel(x, y, width(), height(),
                                  [this](int u, int v) { return intensity(u, v); });
  }
};

/// A level 0 as residuals sample it: the packed float plane (a keyframe not compacted), the
/// intensities alone (compacted), or the 16-bit intensities (compacted with 16-bit images).
/// Exactly one of the three is set.
struct Level0View {
  ImageView<const GradientPixel> full;
  IntensityPlaneView intensity;
  CompactPlaneView compact;
  int width = 0;
  int height = 0;

  bool isCompact() const { return compact.pixels.data != nullptr; }
  bool isIntensity() const { return intensity.pixels.data != nullptr; }
};

/// Owns a compact plane.
class CompactPlane {
 public:
  /// The step a plane whose largest finite magnitude is `max_abs` is stored with: 2^-k with
  /// max_abs * 2^k <= 32767, k at most 14 (0 and tiny planes).
  static float stepFor(float max_abs);

  /// Encodes `intensities`. Returns false (and holds nothing) when one is not finite, which
  /// int16 cannot keep.
  bool encode(ImageView<const float> intensities);
  void clear();
  bool empty() const { return pixels_.empty(); }

  CompactPlaneView view() const {
    return {ImageView<const std::int16_t>(pixels_.data(), width_, height_, width_), step_};
  }
  /// The decoded intensities.
  void copyIntensity(ImageF& out) const;
  std::size_t bytes() const { return pixels_.capacity() * sizeof(std::int16_t); }

 private:
  std::vector<std::int16_t> pixels_;
  int width_ = 0;
  int height_ = 0;
  float step_ = 0.f;
};

/// Bilinear interpolation of the decoded intensity, dx and dy at (x, y), with the arithmetic of
/// interpolateBilinear() on a packed float plane. Requires isInsideForBilinear(x, y, width,
/// height).
inline GradientPixel interpolateBilinear(const CompactPlaneView& image, float x, float y) {
  assert(isInsideForBilinear(x, y, image.width(), image.height()));
  return detail::bilinearPacked(x, y, [&image](int u, int v) { return image.at(u, v); });
}

/// Bilinear (intensity, dx, dy) of whichever plane `image` holds. Requires
/// isInsideForBilinear(x, y, image.width, image.height).
inline GradientPixel interpolateBilinear(const Level0View& image, float x, float y) {
  if (image.isCompact()) return interpolateBilinear(image.compact, x, y);
  if (image.isIntensity()) return interpolateBilinear(image.intensity, x, y);
  return interpolateBilinear(image.full, x, y);
}

}  // namespace ldsm
