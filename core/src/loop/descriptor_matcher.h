// Matching of ORB descriptors between two keyframes: brute-force Hamming search with a maximum
// distance, Lowe's ratio test and a mutual (cross) check, optionally restricted to features that
// fall under the same vocabulary node (the keyframes' FeatureVectors).
#pragma once

#include <cstdint>
#include <vector>

#include "loop/loop_types.h"

namespace ldsm::loop {

/// Settings of matchDescriptors().
struct DescriptorMatchSettings {
  /// Largest accepted Hamming distance (0..256).
  int max_distance = 64;
  /// Best distance must be < ratio * second best distance (1 disables the test).
  float ratio = 0.8f;
  /// Keep a match only if each feature is the other's best match.
  bool mutual_check = true;
  /// Compare only features under the same FeatureVector node when both keyframes have one
  /// (faster, slightly fewer matches); otherwise, or when either is empty, search all features.
  bool use_feature_vector = true;
};

/// One correspondence: feature `query` of the first keyframe, feature `train` of the second.
struct DescriptorMatch {
  std::uint32_t query = 0;
  std::uint32_t train = 0;
  int distance = 0;
};

/// Matches the descriptors of `query` against those of `train`. Result sorted by query index;
/// every query and every train feature appears at most once. Throws InputError when a
/// FeatureVector refers to a feature index out of range or the settings are out of range.
std::vector<DescriptorMatch> matchDescriptors(const KeyframeFeatures& query,
                                              const KeyframeFeatures& train,
                                              const DescriptorMatchSettings& settings);

/// Throws InputError unless pixels, idepth and descriptors of `kf` have the same size, every
/// pixel is finite and every FeatureVector index is in range. `what` names the keyframe in the
/// message (e.g. "current keyframe").
void validateKeyframeFeatures(const KeyframeFeatures& kf, const char* what);

}  // namespace ldsm::loop
