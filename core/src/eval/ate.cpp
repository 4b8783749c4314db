#include "ldsm/eval/ate.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "ldsm/error.h"

namespace ldsm::eval {

namespace {

double median(std::vector<double> v) {
  const std::size_t n = v.size();
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n / 2), v.end());
  const double upper = v[n / 2];
  if (n % 2 == 1) return upper;
  const double lower = *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n / 2));
  return 0.5 * (lower + upper);
}

/// The matched pairs of gt and est, or InputError when fewer than 3.
std::vector<IndexPair> matchedPairs(const Trajectory& gt, const Trajectory& est, double max_dt) {
  std::vector<IndexPair> pairs = associate(gt, est, max_dt);
  if (pairs.size() < 3) {
    throw InputError("ATE: only " + std::to_string(pairs.size()) + " of " +
                     std::to_string(est.size()) +
                     " estimated poses have a ground-truth pose within " + std::to_string(max_dt) +
                     " s; need at least 3 (check the timestamps)");
  }
  return pairs;
}

/// Fills r's errors and statistics from r.pairs and r.alignment.
void measure(const Trajectory& gt, const Trajectory& est, AteResult& r) {
  const std::vector<Eigen::Vector3d> p_gt = gtPositions(gt, r.pairs);
  const std::vector<Eigen::Vector3d> p_est = estPositions(est, r.pairs);
  r.matched = r.pairs.size();
  r.errors.resize(r.matched);
  double sum = 0.0;
  double sum_sq = 0.0;
  double rot_sum_sq = 0.0;
  for (std::size_t i = 0; i < r.matched; ++i) {
    const double e = (r.alignment.apply(p_est[i]) - p_gt[i]).norm();
    r.errors[i] = e;
    sum += e;
    sum_sq += e * e;
    r.max = std::max(r.max, e);
    const Pose aligned = r.alignment.apply(est[r.pairs[i].est].pose);
    const Eigen::Quaterniond diff =
        gt[r.pairs[i].gt].pose.rotation.normalized().conjugate() * aligned.rotation;
    const double angle = 2.0 * std::atan2(diff.vec().norm(), std::abs(diff.w()));
    rot_sum_sq += angle * angle;
  }
  const auto n = static_cast<double>(r.matched);
  r.rmse = std::sqrt(sum_sq / n);
  r.mean = sum / n;
  r.median = median(r.errors);
  r.rotation_rmse_deg = std::sqrt(rot_sum_sq / n) * 180.0 / EIGEN_PI;
  r.gt_path_length = pathLength(p_gt);

  r.aligned_estimate.reserve(est.size());
  for (const StampedPose& sp : est) {
    r.aligned_estimate.push_back({sp.timestamp, r.alignment.apply(sp.pose)});
  }
}

}  // namespace

AteResult computeAte(const Trajectory& gt, const Trajectory& est, AlignMode mode, double max_dt) {
  AteResult r;
  r.pairs = matchedPairs(gt, est, max_dt);
  const std::vector<Eigen::Vector3d> p_gt = gtPositions(gt, r.pairs);
  const std::vector<Eigen::Vector3d> p_est = estPositions(est, r.pairs);
  const Alignment sim3 = alignUmeyama(p_est, p_gt, true);
  r.sim3_scale = sim3.scale;
  r.alignment = mode == AlignMode::Sim3 ? sim3 : alignUmeyama(p_est, p_gt, false);
  measure(gt, est, r);
  return r;
}

AteResult computeAteUnder(const Trajectory& gt, const Trajectory& est, const Alignment& alignment,
                          double max_dt) {
  AteResult r;
  r.pairs = matchedPairs(gt, est, max_dt);
  r.alignment = alignment;
  r.sim3_scale = alignment.scale;
  measure(gt, est, r);
  return r;
}

}  // namespace ldsm::eval
