// Value types shared by the loop-closure modules (features, bag of words, verification, pose
// graph). Internal to core: the public API reports loops as LoopEvent values.
#pragma once

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "ldsm/camera/calibration.h"
#include "ldsm/math/se3.h"
#include "ldsm/math/sim3.h"

namespace ldsm::loop {

/// A 256-bit ORB (rBRIEF) descriptor, bit i of the descriptor in bit (i % 64) of word i / 64.
using OrbDescriptor = std::array<std::uint64_t, 4>;

/// Hamming distance of two descriptors (0..256).
inline int hammingDistance(const OrbDescriptor& a, const OrbDescriptor& b) {
  int d = 0;
  for (int i = 0; i < 4; ++i) d += __builtin_popcountll(a[i] ^ b[i]);
  return d;
}

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

}  // namespace ldsm::loop
