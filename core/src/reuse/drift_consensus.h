// Whether the window has drifted off the map beyond the reach of its own optimisation. A map
// keyframe is brought back only when the window optimisation can pull the window onto it (the
// direct check's basin, about a pixel on fine texture). A window that drifted further (after a
// hard stretch, or a relocalisation a few millimetres off) finds map keyframes that fit its
// newest keyframe well (the direct check's inliers and correlation) but several pixels away, and
// turns every one of them down: a consistent, confident measurement of its drift that nothing
// acted on. When several such keyframes agree on where the newest keyframe is in the map, the
// window is started again from the map (MappingStage::checkDriftOffTheMap, then the tracking
// stage's re-anchoring).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "camera/pyramid_camera.h"
#include "math/se3.h"

namespace ldsm {

/// What one map keyframe says of the newest keyframe's pose in the map.
struct DriftCandidate {
  int id = -1;
  SE3d T_c_w;       ///< the newest keyframe's pose, as this map keyframe's alignment puts it
  int in_view = 0;  ///< its points in view (the tie-break: more evidence first)
};

struct DriftConsensus {
  bool found = false;
  int id = -1;                ///< the candidate whose pose it is
  SE3d T_c_w;                 ///< where the newest keyframe is in the map (the chosen one's pose)
  std::vector<int> agreeing;  ///< the candidates that agree with it (the chosen one included)
  double spread_px = 0.0;     ///< largest disagreement within them (poseDistancePx)
};

/// How far apart two poses of the newest camera put the scene it sees: the mean distance between
/// the projections of the scene points (world coordinates) under the two poses, in pixels. The
/// alignment of one map keyframe's points, all in one part of the image, leaves rotation and
/// translation partly traded against each other; measured on the scene, that trade costs nothing.
double poseDistancePx(const SE3d& a_c_w, const SE3d& b_c_w, const LevelCamera& camera,
                      const std::vector<Eigen::Vector3d>& scene_w);

/// The largest group of candidates that agree within `agreement_px` of one of them (that one's
/// pose is the consensus): found when the group has at least `min_agreeing` members. Ties go to the
/// candidate with more points in view, then the lower id (deterministic).
DriftConsensus findDriftConsensus(const std::vector<DriftCandidate>& candidates,
                                  const LevelCamera& camera,
                                  const std::vector<Eigen::Vector3d>& scene_w, double agreement_px,
                                  int min_agreeing);

/// A frame tracked against the window, carried into the map: the pose that keeps its pose
/// relative to the newest keyframe, given that keyframe's pose in the window's world and in the
/// map's (world -> camera poses). Where the tracking stage starts the re-anchored window.
inline SE3d carriedIntoMap(const SE3d& frame_T_c_w, const SE3d& newest_T_c_w_window,
                           const SE3d& newest_T_c_w_map) {
  return frame_T_c_w * newest_T_c_w_window.inverse() * newest_T_c_w_map;
}

}  // namespace ldsm
