// Pre-filtered (mip-mapped) single-channel textures of the synthetic renderer.
//
// Texels are vertex-centred: texel k of a level sits at level-0 texel coordinate k / scale, and
// each level is made from the previous one with the separable [1/4 1/2 1/4] filter, halving the
// texel count along every axis that still has more than two (clamped) or one (repeating) texels.
// A texture either repeats (power-of-two size, coordinates wrap) or is clamped at its border.
#pragma once

#include <vector>

#include "ldsm/image.h"

namespace ldsm::drivers::sim {

struct MipLevel {
  int width = 0;   ///< texels per row
  int height = 0;  ///< rows
  /// Level texels per level-0 texel along u and v (1, 1/2, 1/4, ... while the axis shrinks).
  double scale_u = 1.0, scale_v = 1.0;
  /// (width + 1) x (height + 1) texels: the extra last column and row repeat the first ones
  /// (repeating texture) or the last ones (clamped), so a bilinear lookup needs no wrapping.
  ImageF texels;

  float at(int x, int y) const { return texels(x, y); }
};

struct MipTexture {
  bool wrap = false;             ///< repeat (power-of-two sizes) or clamp to the border texel
  double texel_size_m = 0.01;    ///< metres per level-0 texel on the surface
  std::vector<MipLevel> levels;  ///< levels[0] is the full resolution

  int levelCount() const { return static_cast<int>(levels.size()); }
};

/// Builds the mip chain of `base`. Repeating textures must have power-of-two sizes and are reduced
/// down to 1x1; clamped ones (at least 2x2) down to 2x2. Throws ldsm::InputError otherwise.
MipTexture buildMipTexture(const ImageF& base, bool wrap, double texel_size_m);

/// Bilinear value of level `level` at level-0 texel coordinates (s, t) (scaled to the level,
/// wrapped or clamped). Reference implementation in double; the renderer uses an equivalent
/// float path.
double sampleLevelBilinear(const MipTexture& texture, int level, double s, double t);

}  // namespace ldsm::drivers::sim
