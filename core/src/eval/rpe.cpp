#include "ldsm/eval/rpe.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "ldsm/error.h"
#include "ldsm/eval/association.h"

namespace ldsm::eval {

std::vector<double> defaultRpeLengths(double path_length) {
  std::vector<double> lengths;
  if (!(path_length > 0.0) || !std::isfinite(path_length)) return lengths;
  for (int k = 1; k <= 8; ++k) {
    lengths.push_back(path_length >= 800.0 ? 100.0 * k : path_length * 0.1 * k);
  }
  return lengths;
}

namespace {

void checkOptions(const RpeOptions& o) {
  for (double l : o.lengths) {
    if (!(l > 0.0) || !std::isfinite(l)) {
      throw ConfigError("RPE: segment lengths must be finite and > 0 m, got " + std::to_string(l));
    }
  }
  if (o.step == 0) throw ConfigError("RPE: step must be >= 1");
  if (!(o.scale > 0.0) || !std::isfinite(o.scale)) {
    throw ConfigError("RPE: scale must be finite and > 0, got " + std::to_string(o.scale));
  }
}

Eigen::Isometry3d scaledIsometry(const Pose& p, double scale) {
  Pose s = p;
  s.translation *= scale;
  return s.isometry();
}

double rotationAngle(const Eigen::Matrix3d& r) {
  const Eigen::Quaterniond q(r);
  return 2.0 * std::atan2(q.vec().norm(), std::abs(q.w()));
}

}  // namespace

RpeResult computeRpe(const Trajectory& gt, const Trajectory& est, const RpeOptions& options) {
  checkOptions(options);
  const std::vector<IndexPair> pairs = associate(gt, est, options.max_dt);
  const std::vector<Eigen::Vector3d> p_gt = gtPositions(gt, pairs);

  // Distance travelled along the ground truth up to each matched pose.
  std::vector<double> dist(pairs.size(), 0.0);
  for (std::size_t i = 1; i < pairs.size(); ++i) {
    dist[i] = dist[i - 1] + (p_gt[i] - p_gt[i - 1]).norm();
  }
  const std::vector<double> lengths = options.lengths.empty()
                                          ? defaultRpeLengths(dist.empty() ? 0.0 : dist.back())
                                          : options.lengths;

  RpeResult result;
  double t_sum = 0.0;
  double r_sum = 0.0;
  for (double length : lengths) {
    RpeLengthStats stats;
    stats.length = length;
    double lt_sum = 0.0;
    double lr_sum = 0.0;
    for (std::size_t first = 0; first < pairs.size(); first += options.step) {
      // First pose at least `length` further along the ground truth.
      const auto it = std::lower_bound(dist.begin() + static_cast<std::ptrdiff_t>(first),
                                       dist.end(), dist[first] + length);
      if (it == dist.end()) break;
      const auto last = static_cast<std::size_t>(it - dist.begin());
      const Eigen::Isometry3d gt_delta =
          gt[pairs[first].gt].pose.isometry().inverse() * gt[pairs[last].gt].pose.isometry();
      const Eigen::Isometry3d est_delta =
          scaledIsometry(est[pairs[first].est].pose, options.scale).inverse() *
          scaledIsometry(est[pairs[last].est].pose, options.scale);
      const Eigen::Isometry3d error = est_delta.inverse() * gt_delta;
      lt_sum += error.translation().norm() / length;
      lr_sum += rotationAngle(error.linear()) / length;
      ++stats.segments;
    }
    if (stats.segments > 0) {
      stats.translation_percent = 100.0 * lt_sum / static_cast<double>(stats.segments);
      stats.rotation_deg_per_m = lr_sum / static_cast<double>(stats.segments) * 180.0 / EIGEN_PI;
    }
    t_sum += lt_sum;
    r_sum += lr_sum;
    result.segments += stats.segments;
    result.per_length.push_back(stats);
  }
  if (result.segments > 0) {
    result.translation_percent = 100.0 * t_sum / static_cast<double>(result.segments);
    result.rotation_deg_per_m = r_sum / static_cast<double>(result.segments) * 180.0 / EIGEN_PI;
  }
  return result;
}

}  // namespace ldsm::eval
