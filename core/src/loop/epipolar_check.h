// Geometric verification of a place match between two images without depth: a fundamental
// matrix fitted by RANSAC (OpenCV, fixed seed) to the descriptor matches, accepted when enough
// matches agree with it. Used to evaluate place recognition on still images.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "loop/descriptor_matcher.h"

namespace ldsm::loop {

/// Settings of checkEpipolar().
struct EpipolarCheckSettings {
  int min_inliers = 20;       ///< matches consistent with F needed to accept
  double threshold_px = 2.0;  ///< RANSAC distance to the epipolar line (pixels)
  double confidence = 0.999;
  int max_iterations = 2000;
};

struct EpipolarCheckResult {
  int matches = 0;
  int inliers = 0;
  bool accepted = false;
};

/// Fits F to `matches` (query indices into `a`, train indices into `b`) and counts inliers.
/// Fewer than 8 matches (or fewer than min_inliers) are rejected without fitting. Throws
/// InputError when a match index is out of range.
EpipolarCheckResult checkEpipolar(const std::vector<Eigen::Vector2f>& a,
                                  const std::vector<Eigen::Vector2f>& b,
                                  const std::vector<DescriptorMatch>& matches,
                                  const EpipolarCheckSettings& settings = {});

}  // namespace ldsm::loop
