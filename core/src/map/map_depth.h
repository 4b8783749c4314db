// How far the map's points are from the keyframes that see them: the unit the map-relative
// tolerances scale with (relocalisation's search radius, whether two poses agree). A window
// measures it from its own points; a map loaded before any window exists is measured here.
#pragma once

#include <optional>
#include <vector>

#include "map/map_store.h"
#include "model/patch_point.h"

namespace ldsm {

/// The median depth of the points with a positive inverse depth, in their host keyframe's units
/// (the element at half the count of the sorted depths); nothing without such a point.
std::optional<double> medianHostDepth(const std::vector<PatchPoint>& points);

/// The median, over the keyframes of `map` that hold points, of each keyframe's median depth
/// in world units (its record's Sim(3) scale applied); nothing when no keyframe holds a point.
std::optional<double> medianKeyframeDepth(const StoredMap& map);

}  // namespace ldsm
