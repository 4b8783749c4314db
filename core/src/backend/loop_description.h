// What loop closure gets of a keyframe leaving the window: more corners than the odometry's own
// (describeForLoopClosure) and depths for them (fillCornerDepths). Verification needs
// 3D points on the candidate keyframe (PnP) and helps itself with depths on the current one
// (Sim(3) 3D-3D terms), but only the corners that became active points have a depth of their own
// (about a third of them on vamr_desk_loop). The others get one from
//  1. their immature point, when its depth interval has converged well enough (looser than
//     activation: the interval at most kMaxRelativeWidth of the estimate), or
//  2. the active points of the whole window projected into the keyframe: the median inverse depth
//     of those within kNeighbourRadius pixels, when at least kMinNeighbours agree within
//     kMaxSpread (max / min), so that corners on depth edges stay without depth.
#pragma once

#include <memory>
#include <vector>

#include "backend/window_keyframe.h"
#include "camera/pyramid_camera.h"
#include "model/marginalized_keyframe.h"

namespace ldsm {

struct CornerDepthFill {
  static constexpr float kMaxRelativeWidth = 0.5f;
  static constexpr float kMinQuality = 2.f;
  static constexpr float kNeighbourRadius = 4.f;
  static constexpr int kMinNeighbours = 3;
  static constexpr float kMaxSpread = 1.25f;

  int from_points = 0;      ///< corners that were active points
  int from_immature = 0;    ///< from a converged immature point
  int from_neighbours = 0;  ///< from projected active points nearby
  int without = 0;          ///< left without depth
};

/// Fills the NaN entries of kf.corner_idepth (kf must be in `window`, its immature points and
/// the window's active points still present). Returns the counts.
CornerDepthFill fillCornerDepths(WindowKeyframe& kf,
                                 const std::vector<std::unique_ptr<WindowKeyframe>>& window,
                                 const LevelCamera& camera);

/// Appends to `corners` (the odometry's) those of `loop_corners` at least 4 px away from each of
/// them.
void appendLoopCorners(const std::vector<Eigen::Vector2f>& loop_corners,
                       std::vector<Eigen::Vector2f>& corners);

/// Fills the loop-closure description of `f` (in `window`) into `out`: the odometry's corners plus
/// its loop corners (appendLoopCorners; they join f.corners) and their depths. The level-0 image
/// is handed on by the caller once the keyframe is no longer sampled
/// (ImagePyramid::takeIntensity0).
void describeForLoopClosure(WindowKeyframe& f,
                            const std::vector<std::unique_ptr<WindowKeyframe>>& window,
                            const LevelCamera& camera, MarginalizedKeyframe& out);

}  // namespace ldsm
