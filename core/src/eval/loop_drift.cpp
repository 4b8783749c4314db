#include "ldsm/eval/loop_drift.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "ldsm/error.h"

namespace ldsm::eval {

namespace {

Alignment alignSegment(const Trajectory& gt, const Trajectory& est,
                       const std::vector<IndexPair>& segment, const char* name) {
  try {
    return alignUmeyama(estPositions(est, segment), gtPositions(gt, segment), true);
  } catch (const InputError& e) {
    throw InputError(std::string("loop drift: ") + name + " segment: " + e.what());
  }
}

double rmsDistance(const Alignment& a, const Alignment& b,
                   const std::vector<Eigen::Vector3d>& points) {
  if (points.empty()) return 0.0;
  double sum_sq = 0.0;
  for (const auto& p : points) sum_sq += (a.apply(p) - b.apply(p)).squaredNorm();
  return std::sqrt(sum_sq / static_cast<double>(points.size()));
}

}  // namespace

LoopDriftResult computeLoopDrift(const Trajectory& gt, const Trajectory& est,
                                 const std::vector<IndexPair>& start_segment,
                                 const std::vector<IndexPair>& end_segment) {
  LoopDriftResult r;
  r.start_alignment = alignSegment(gt, est, start_segment, "start");
  r.end_alignment = alignSegment(gt, est, end_segment, "end");
  r.start_poses = start_segment.size();
  r.end_poses = end_segment.size();

  r.drift = r.end_alignment * r.start_alignment.inverse();
  r.translation_drift = r.drift.translation.norm();
  r.rotation_drift_deg = r.drift.rotationAngle() * 180.0 / EIGEN_PI;
  r.scale_drift = r.drift.scale;

  std::vector<Eigen::Vector3d> all;
  all.reserve(est.size());
  for (const StampedPose& sp : est) all.push_back(sp.pose.translation);
  r.alignment_error = rmsDistance(r.start_alignment, r.end_alignment, all);

  std::vector<Eigen::Vector3d> segments = estPositions(est, start_segment);
  for (const auto& p : estPositions(est, end_segment)) segments.push_back(p);
  r.alignment_error_segments = rmsDistance(r.start_alignment, r.end_alignment, segments);
  return r;
}

LoopDriftResult computeLoopDrift(const Trajectory& gt, const Trajectory& est,
                                 const LoopDriftOptions& options) {
  const std::vector<IndexPair> pairs = associate(gt, est, options.max_dt);
  const std::size_t n = options.segment_poses > 0 ? options.segment_poses
                                                  : std::max<std::size_t>(3, pairs.size() / 5);
  if (n < 3 || 2 * n > pairs.size()) {
    throw InputError("loop drift: needs two disjoint segments of " + std::to_string(n) +
                     " (>= 3) matched poses, but only " + std::to_string(pairs.size()) +
                     " poses match");
  }
  const std::vector<IndexPair> start(pairs.begin(), pairs.begin() + static_cast<std::ptrdiff_t>(n));
  const std::vector<IndexPair> end(pairs.end() - static_cast<std::ptrdiff_t>(n), pairs.end());
  return computeLoopDrift(gt, est, start, end);
}

}  // namespace ldsm::eval
