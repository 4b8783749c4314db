// The consistency checks of a map (docs/map-file.md, "What the loader checks"): finite numbers
// where a NaN or an infinity cannot be, ids that exist. decodeMap runs them on what it read (an
// InputError naming the file), encodeMap on what it is given (so a map it writes always loads).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "mapfile/map_data.h"

namespace ldsm::mapfile {

struct MapProblem {
  std::uint32_t section = 0;  ///< the tag of the section at fault (map_format.h)
  std::string what;           ///< "keyframe 12: point 3: inverse depth nan is not positive"
};

/// The first problem found, section by section in file order; nothing when the map is sound.
std::optional<MapProblem> findMapProblem(const MapData& map);

/// A number for messages ("nan", "inf", "1.5", "0.000123").
std::string numberText(double v);

}  // namespace ldsm::mapfile
