#include "ldsm/eval/association.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "ldsm/error.h"

namespace ldsm::eval {

namespace {

struct Candidate {
  double dt;
  std::size_t gt;
  std::size_t est;
};

// Indices of a trajectory sorted by timestamp (stable for equal stamps).
std::vector<std::size_t> timeOrder(const Trajectory& t) {
  std::vector<std::size_t> order(t.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&t](std::size_t a, std::size_t b) { return t[a].timestamp < t[b].timestamp; });
  return order;
}

}  // namespace

std::vector<IndexPair> associate(const Trajectory& gt, const Trajectory& est, double max_dt) {
  if (!std::isfinite(max_dt) || max_dt < 0.0) {
    throw ConfigError("association: max_dt must be a finite value >= 0 s, got " +
                      std::to_string(max_dt));
  }
  const std::vector<std::size_t> gt_order = timeOrder(gt);
  std::vector<double> gt_times(gt.size());
  for (std::size_t k = 0; k < gt.size(); ++k) gt_times[k] = gt[gt_order[k]].timestamp;

  std::vector<Candidate> candidates;
  for (std::size_t e = 0; e < est.size(); ++e) {
    const double t = est[e].timestamp;
    if (!std::isfinite(t)) continue;
    auto it = std::lower_bound(gt_times.begin(), gt_times.end(), t - max_dt);
    for (; it != gt_times.end() && *it <= t + max_dt; ++it) {
      const auto k = static_cast<std::size_t>(it - gt_times.begin());
      candidates.push_back({std::abs(*it - t), gt_order[k], e});
    }
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& a, const Candidate& b) { return a.dt < b.dt; });

  std::vector<bool> gt_used(gt.size(), false);
  std::vector<bool> est_used(est.size(), false);
  std::vector<IndexPair> pairs;
  for (const Candidate& c : candidates) {
    if (gt_used[c.gt] || est_used[c.est]) continue;
    gt_used[c.gt] = true;
    est_used[c.est] = true;
    pairs.push_back({c.gt, c.est});
  }
  std::sort(pairs.begin(), pairs.end(),
            [](const IndexPair& a, const IndexPair& b) { return a.est < b.est; });
  return pairs;
}

std::vector<Eigen::Vector3d> gtPositions(const Trajectory& gt,
                                         const std::vector<IndexPair>& pairs) {
  std::vector<Eigen::Vector3d> out;
  out.reserve(pairs.size());
  for (const auto& p : pairs) out.push_back(gt.at(p.gt).pose.translation);
  return out;
}

std::vector<Eigen::Vector3d> estPositions(const Trajectory& est,
                                          const std::vector<IndexPair>& pairs) {
  std::vector<Eigen::Vector3d> out;
  out.reserve(pairs.size());
  for (const auto& p : pairs) out.push_back(est.at(p.est).pose.translation);
  return out;
}

double pathLength(const std::vector<Eigen::Vector3d>& points) {
  double length = 0.0;
  for (std::size_t i = 1; i < points.size(); ++i) length += (points[i] - points[i - 1]).norm();
  return length;
}

}  // namespace ldsm::eval
