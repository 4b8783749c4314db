// The repeating albedo patterns shared by the quads of every synthetic scene.
#pragma once

#include <cstdint>
#include <vector>

#include "ldsm/drivers/sim/mip_texture.h"

namespace ldsm::drivers::sim {

/// Indices into the library returned by makeTextureLibrary().
enum TextureId : int {
  kPlaster = 0,
  kBrick,
  kFloorTiles,
  kWood,
  kCeilingPanels,
  kChecker,
  kBlobs,
  kConcrete,
  kTextureCount
};

/// Size in texels of every library texture (square, repeating).
inline constexpr int kLibraryTextureSize = 512;
/// Metres per level-0 texel of the library textures (a tile is 2.56 m).
inline constexpr double kLibraryTexelSize = 0.005;

/// Bakes the library (kTextureCount repeating, mip-mapped textures with albedo in (0, 1)).
std::vector<MipTexture> makeTextureLibrary(std::uint32_t seed);

}  // namespace ldsm::drivers::sim
