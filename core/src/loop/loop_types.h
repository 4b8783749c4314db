// Value types shared by the loop-closure modules (features, bag of words, verification, pose
// graph). Internal to core: the public API reports loops as LoopEvent values.
#pragma once

#include <array>
#include <cstdint>
#include <map>
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

/// What the loop closer hands to the mapper after a closed loop.
struct LoopCorrection {
  int current_keyframe_id = -1;
  int candidate_keyframe_id = -1;
  int inliers = 0;
  double scale = 1.0;  ///< of S_current_candidate
  /// Corrected world-from-camera poses by keyframe id (the keyframes outside the active window;
  /// the mapper moves their points with them and must not overwrite the active window).
  std::map<int, Sim3d> S_world_camera;  ///< empty when the drift was not significant
  double drift_chi2 = 0.0;              ///< see LoopClosureEvent::drift_chi2
  double time_ms = 0.0;
};

}  // namespace ldsm::loop
