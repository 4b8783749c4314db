// The packed per-pixel record of a pyramid level: intensity and its image gradient.
#pragma once

namespace ldsm {

/// Intensity and central-difference gradient of one pixel, packed as three floats (12 bytes), so
/// that one bilinear lookup fetches all three.
struct GradientPixel {
  float intensity;
  float dx;  ///< (I(x+1, y) - I(x-1, y)) / 2, zero on the image border
  float dy;  ///< (I(x, y+1) - I(x, y-1)) / 2, zero on the image border
};
static_assert(sizeof(GradientPixel) == 3 * sizeof(float), "GradientPixel must be packed");

}  // namespace ldsm
