// Value types shared by the loop-closure modules (features, bag of words, verification, pose
// graph). Internal to core: the public API reports loops as LoopEvent values.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "ldsm/camera/calibration.h"
#include "math/se3.h"
#include "math/sim3.h"
#include "model/orb_descriptor.h"

namespace ldsm::loop {

/// Visual word id of a vocabulary leaf.
using WordId = std::uint32_t;

/// Sparse bag-of-words vector: (word, tf-idf weight) sorted by word, L1-normalised.
using BowVector = std::vector<std::pair<WordId, float>>;

/// Direct index entry: for a node at a chosen vocabulary level, the features that fall under it.
using FeatureVector = std::vector<std::pair<std::uint32_t, std::vector<std::uint32_t>>>;

/// What the loop closer keeps of one keyframe. Pixel coordinates are in the rectified pinhole
/// camera the engine works in; `idepth[i]` is the inverse depth of feature i in this keyframe
/// (<= 0 or NaN when unknown), from the odometry's optimised points.
struct KeyframeFeatures {
  int keyframe_id = -1;
  double timestamp = 0.0;
  PinholeIntrinsics camera;
  std::vector<Eigen::Vector2f> pixels;
  std::vector<float> idepth;
  std::vector<OrbDescriptor> descriptors;
  BowVector bow;
  FeatureVector feature_vector;
};

/// A verified loop: `current` recognised the place of `candidate`.
struct DetectedLoop {
  int current_keyframe_id = -1;
  int candidate_keyframe_id = -1;
  int inliers = 0;
  double scale = 1.0;        ///< of S_current_candidate
  double drift_chi2 = 0.0;   ///< see LoopClosureEvent::drift_chi2
  bool significant = false;  ///< drift_chi2 >= loop.correction_chi2: the pose graph corrects it
  /// How much more drift the loop shows than the odometry's drift model expects (>= 1; the
  /// pose graph weakens the odometry edges by it).
  double drift_scale = 1.0;
  double time_ms = 0.0;  ///< detection and verification (and the pose graph that corrected it)
};

/// A loop that connected two maps (the current one and one started earlier, before tracking was
/// lost for good): the earlier map was moved into the current one's frame.
struct MapMerge {
  int from_map = -1;  ///< the earlier map (its number, in order of creation; 0: the first)
  int into_map = -1;  ///< the current map
  Sim3d S_into_from;  ///< internal coordinates of the earlier map -> the current map's
  std::map<int, Sim3d> S_world_camera;  ///< the earlier map's keyframes, moved
  int current_keyframe_id = -1;
  int candidate_keyframe_id = -1;
};

/// What the loop closer hands to the mapper: the loops verified since the last hand-over (the
/// significant ones once the pose graph that includes them has run), and the poses that graph
/// corrected.
struct LoopCorrection {
  std::vector<DetectedLoop> loops;
  /// Corrected world-from-camera poses by keyframe id (the keyframes outside the active window;
  /// the mapper moves their points with them and must not overwrite the active window). Empty
  /// when nothing is corrected.
  std::map<int, Sim3d> S_world_camera;
  /// Significant constraints from map keyframes brought back into the window (map reuse) that
  /// this correction includes.
  int reuse_constraints = 0;
  /// A loop connected two maps (applied before S_world_camera).
  std::optional<MapMerge> merge;
  /// Keyframes taken out of the pose graph since the last result (culled or forgotten ones,
  /// PoseGraph::foldVertex), each with the vertex it was folded into: from now on it moves with
  /// that vertex (applied before the rest).
  std::vector<std::pair<int, int>> folded;
};

}  // namespace ldsm::loop
