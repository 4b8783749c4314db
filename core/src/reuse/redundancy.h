// Whether a keyframe leaving the window adds anything to the map: it does not when a map keyframe
// from an earlier visit stands at nearly the same place, looks the same way, and sees nearly all
// of its points. Such a keyframe keeps only its pose (frames were tracked against it), so the map
// grows with the space explored, not with the time spent in it.
#pragma once

#include "camera/pyramid_camera.h"
#include "ldsm/config.h"
#include "map/map_store.h"
#include "model/marginalized_keyframe.h"

namespace ldsm {

struct RedundancyCheck {
  bool redundant = false;
  int covered_by = -1;    ///< the map keyframe that covers it
  double coverage = 0.0;  ///< share of its points that keyframe sees
};

/// Checks `keyframe` (at its current pose record `pose`) against the map keyframes near it.
RedundancyCheck checkRedundancy(const MarginalizedKeyframe& keyframe, const KeyframeRecord& pose,
                                const MapStore& map, const LevelCamera& camera,
                                const ReuseConfig& config);

}  // namespace ldsm
