// Per-quad detail maps: unique landmarks (posters, doors, lamps, floor mats, labels, skirting)
// multiplied by the lighting of the scene's point lights, baked at kDetailTexelSize.
#pragma once

#include <cstdint>

#include "ldsm/drivers/sim/sim_scene.h"

namespace ldsm::drivers::sim {

/// Metres per level-0 texel of the detail maps (4 library texels, so mip levels line up).
inline constexpr double kDetailTexelSize = 0.02;

/// Bakes the detail map of scene.quads[quad] (the quad's landmarks come from hashing `seed` and the
/// quad index; lighting from scene.lights).
MipTexture bakeDetailMap(const SimScene& scene, int quad, std::uint32_t seed);

}  // namespace ldsm::drivers::sim
