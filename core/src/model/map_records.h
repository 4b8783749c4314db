// The records the map keeps, as values: a keyframe's pose, a frame's pose relative to the
// keyframe it was tracked against, and a point that left the window with its host keyframe.
#pragma once

#include <cstdint>

#include "ldsm/types.h"
#include "math/se3.h"

namespace ldsm {

struct KeyframeRecord {
  int id = 0;
  std::int64_t frame_index = 0;
  double timestamp = 0.0;
  SE3d T_w_c;  ///< camera-to-world
  /// Scale of the keyframe's Sim(3) after a loop correction: frames tracked against it are at
  /// T_w_c * (scale * their relative translation).
  double scale = 1.0;
  /// The map it was made in (map/map_frames.h; 0: the first map).
  int map = 0;
};

struct FrameRecord {
  std::int64_t frame_index = 0;
  double timestamp = 0.0;
  int reference_keyframe = -1;  ///< id of the keyframe the frame was tracked against
  SE3d T_ref_c;                 ///< frame pose relative to that keyframe
};

/// A point that left the window, with the id of the keyframe that hosted it (-1: none); it moves
/// with that keyframe on loop closure.
struct HostedPoint {
  MapPoint point;
  int host = -1;
};

}  // namespace ldsm
