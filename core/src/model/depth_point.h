// A point with depth as the tracker's reference sees it: the window's active points projected
// into the newest keyframe (what the coarse tracker aligns the next frames to).
#pragma once

namespace ldsm {

/// A point of the window projected into the reference keyframe.
struct DepthPoint {
  float u = 0;       ///< level-0 pixel column in the reference
  float v = 0;       ///< level-0 pixel row in the reference
  float idepth = 0;  ///< inverse depth in the reference frame, > 0
  float weight = 1;  ///< confidence (e.g. inverse variance of the inverse depth), > 0
  /// Hosted by a map keyframe brought back into the window (reuse), seen from elsewhere: where
  /// it and the window's points meet at a pixel, one of them may be occluded.
  bool from_map = false;
};

}  // namespace ldsm
