// Matching the poses of two trajectories by timestamp.
#pragma once

#include <cstddef>
#include <vector>

#include "ldsm/types.h"

namespace ldsm::eval {

/// A ground-truth pose and the estimated pose matched to it.
struct IndexPair {
  std::size_t gt = 0;
  std::size_t est = 0;
};

/// Matches poses one-to-one by nearest timestamp: every candidate pair with |t_gt - t_est| <=
/// max_dt is considered, closest pairs first, and each pose is used at most once (as in the TUM
/// RGB-D benchmark's associate.py). Result is sorted by estimate index (and so by time when the
/// trajectories are time-ordered). Throws ldsm::ConfigError when max_dt is negative or not finite.
std::vector<IndexPair> associate(const Trajectory& gt, const Trajectory& est, double max_dt);

/// Positions of the matched poses, in pair order.
std::vector<Eigen::Vector3d> gtPositions(const Trajectory& gt, const std::vector<IndexPair>& pairs);
std::vector<Eigen::Vector3d> estPositions(const Trajectory& est,
                                          const std::vector<IndexPair>& pairs);

/// Length of the polyline through the points (sum of consecutive distances).
double pathLength(const std::vector<Eigen::Vector3d>& points);

}  // namespace ldsm::eval
