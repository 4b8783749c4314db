// The level-0 (intensity, dx, dy) plane of a keyframe that is only the target of residuals, in
// 16-bit fixed point: 6 instead of 12 bytes per pixel. Stored values are round(value * scale) with
// scale a power of two, the finest at which the plane's largest magnitude fits into int16 (128 for
// grey levels up to 255: steps of 1/128 grey level), so decoding (stored * 2^-k) is exact and the
// bilinear interpolation of decoded values is that of the float plane on values rounded to the
// step.
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

/// Intensity and gradient of one pixel as int16 multiples of the plane's step.
struct CompactGradientPixel {
  std::int16_t intensity;
  std::int16_t dx;
  std::int16_t dy;
};
static_assert(sizeof(CompactGradientPixel) == 3 * sizeof(std::int16_t),
              "CompactGradientPixel must be packed");

/// A compact plane as readers take it: value = stored * step.
struct CompactPlaneView {
  /// The pixels; one more element is readable past the last pixel (4-lane loads of a pixel read
  /// the next pixel's intensity).
  ImageView<const CompactGradientPixel> pixels;
  float step = 0.f;  ///< a power of two

  int width() const { return pixels.width; }
  int height() const { return pixels.height; }
  GradientPixel at(int x, int y) const {
    const CompactGradientPixel& c = pixels(x, y);
    return {step * static_cast<float>(c.intensity), step * static_cast<float>(c.dx),
            step * static_cast<float>(c.dy)};
  }
};

/// A level 0 as residuals sample it: the packed float plane (a keyframe not compacted), the
/// intensities alone (compacted), or the 16-bit plane (compacted with 16-bit images). Exactly one
/// of the three is set.
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

  /// Encodes `plane`. Returns false (and holds nothing) when the plane holds a non-finite value,
  /// which int16 cannot keep.
  bool encode(ImageView<const GradientPixel> plane);
  void clear();
  bool empty() const { return pixels_.empty(); }

  CompactPlaneView view() const {
    return {ImageView<const CompactGradientPixel>(pixels_.data(), width_, height_, width_), step_};
  }
  /// The decoded intensities.
  void copyIntensity(ImageF& out) const;
  std::size_t bytes() const { return pixels_.capacity() * sizeof(CompactGradientPixel); }

 private:
  std::vector<CompactGradientPixel> pixels_;
  int width_ = 0;
  int height_ = 0;
  float step_ = 0.f;
};

/// Bilinear interpolation of the decoded intensity, dx and dy at (x, y), with the arithmetic of
/// interpolateBilinear() on a float plane. Requires isInsideForBilinear(x, y, width, height).
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
