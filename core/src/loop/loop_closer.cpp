#include "loop/loop_closer.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/LU>

namespace ldsm::loop {

LoopCloser::LoopCloser(const LoopConfig& config, const PinholeIntrinsics& camera, bool inline_mode)
    : config_(config), camera_(camera), drift_(OdometryDriftModel::fromConfig(config)) {
  verification_.min_inliers = config.min_inliers;
  concurrency::TaskOptions options;
  options.mode = inline_mode ? concurrency::TaskMode::kInline : concurrency::TaskMode::kThreaded;
  options.queue_capacity = static_cast<std::size_t>(config.queue_capacity);
  task_ = std::make_unique<concurrency::BackgroundTask<LoopJob, LoopCorrection>>(
      [this](LoopJob& job, const std::atomic<bool>& abort) { return process(job, abort); },
      options);
}

LoopCloser::~LoopCloser() {
  task_->stop();
}

void LoopCloser::keyframeLeftWindow(MarginalizedKeyframe&& kf) {
  const int id = kf.id;
  if (!task_->submit(std::move(kf)))
    spdlog::debug("loop closure: queue full, keyframe {} not indexed", id);
}

void LoopCloser::waitIdle() {
  if (!task_->waitIdle(std::chrono::seconds(60)))
    spdlog::warn("loop closure: background task still busy after 60 s");
}

void LoopCloser::addToGraph(const LoopJob& job, bool new_map) {
  const int id = job.id;
  if (last_id_ >= 0 && graph_.hasVertex(last_id_) && !new_map) {
    // Odometry edge from the window's final relative pose (never from earlier graph results).
    const Sim3d S_prev_cur(last_T_w_c_.inverse() * job.T_w_c);
    graph_.addVertex(id, graph_.vertex(last_id_) * S_prev_cur);
    graph_.addEdge(PoseGraphEdge{last_id_, id, S_prev_cur, drift_.edgeInformation(S_prev_cur),
                                 PoseGraphEdgeKind::kOdometry});
    const ChainPosition& prev = chain_.at(last_id_);
    chain_[id] = {prev.step + 1, prev.path + S_prev_cur.translation().norm()};
  } else {
    graph_.addVertex(id, Sim3d(job.T_w_c));
    // A new map: not connected to the old chain by any odometry.
    chain_[id] = {last_id_ >= 0 ? chain_.at(last_id_).step + kDisconnectedSteps : 0, 0.0};
  }
  last_id_ = id;
  last_T_w_c_ = job.T_w_c;
}

std::optional<LoopCorrection> LoopCloser::process(LoopJob& job, const std::atomic<bool>& abort) {
  const int id = job.id;
  addToGraph(job, new_map_.exchange(false));
  KeyframeFeatures f;
  f.keyframe_id = id;
  f.timestamp = job.timestamp;
  f.camera = camera_;
  f.pixels = std::move(job.corners);
  f.idepth = std::move(job.corner_idepth);
  f.descriptors = std::move(job.descriptors);
  f.idepth.resize(f.pixels.size(), NAN);
  index_.add(id, f.descriptors);
  index_.retrainIfDue(&abort);
  features_[id] = std::move(f);
  std::optional<LoopCorrection> result = closeLoop(id, abort);
  if (job.culled) {
    // Redundant with the map: it looks for loops, but is no place to be found itself.
    index_.remove(id);
    features_.erase(id);
  }
  return result;
}

std::optional<LoopCorrection> LoopCloser::closeLoop(int id, const std::atomic<bool>& abort) {
  const auto t0 = std::chrono::steady_clock::now();
  const int recent = config_.exclude_recent_keyframes;
  const std::vector<PlaceCandidate> candidates = index_.query(
      id, [&](int k) { return k > id - recent; }, config_.max_candidates);
  KeyframeFeatures& current = features_[id];
  if (const FeatureVector* fv = index_.featureVector(id)) current.feature_vector = *fv;
  for (const PlaceCandidate& c : candidates) {
    const auto it = features_.find(c.keyframe_id);
    if (it == features_.end() || !graph_.hasVertex(c.keyframe_id)) continue;
    KeyframeFeatures& candidate = it->second;
    if (const FeatureVector* fv = index_.featureVector(c.keyframe_id))
      candidate.feature_vector = *fv;
    const LoopVerification v = verifyLoop(current, candidate, verification_);
    if (!v.accepted) {
      spdlog::debug("loop {} -> {} (score {:.3f}) rejected: {}", id, c.keyframe_id, c.score,
                    v.reason);
      continue;
    }
    // How far the measurement is from what the graph already says, in units of the loop's
    // uncertainty plus the drift the odometry chain between the two may have accumulated.
    const Sim3d implied = graph_.vertex(id).inverse() * graph_.vertex(c.keyframe_id);
    const Vector7d d = (implied * v.S_current_candidate.inverse()).log();
    const Matrix7d loop_cov = v.information.inverse();
    const ChainPosition& pa = chain_.at(id);
    const ChainPosition& pb = chain_.at(c.keyframe_id);
    const Matrix7d chain_cov =
        drift_.chainCovariance(pa.step - pb.step, std::fabs(pa.path - pb.path), implied);
    const double drift_chi2 = d.dot(Eigen::LDLT<Matrix7d>(loop_cov + chain_cov).solve(d));
    // Loop edge candidate -> current: S_cand_cur = S_w_cand^-1 S_w_cur; its residual is the
    // loop's own tangent error, so the edge takes the loop's information as it is.
    graph_.addEdge(PoseGraphEdge{c.keyframe_id, id, v.S_current_candidate.inverse(), v.information,
                                 PoseGraphEdgeKind::kLoop});
    LoopCorrection out;
    out.current_keyframe_id = id;
    out.candidate_keyframe_id = c.keyframe_id;
    out.inliers = v.num_inliers;
    out.scale = v.S_current_candidate.scale();
    out.drift_chi2 = drift_chi2;
    auto elapsed = [&] {
      return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
          .count();
    };
    if (drift_chi2 < config_.correction_chi2) {
      // The odometry already agrees with the loop within the loop's own accuracy: a correction
      // would only move the trajectory by the measurement's noise. The edge stays in the graph
      // for later corrections.
      out.time_ms = elapsed();
      spdlog::info(
          "loop found: keyframe {} -> {} ({} inliers, scale {:.3f}); drift not significant "
          "(chi2 {:.1f} < {:.1f}), nothing to correct",
          id, c.keyframe_id, out.inliers, out.scale, drift_chi2, config_.correction_chi2);
      return out;
    }
    if (fixed_id_ >= 0) graph_.setFixed(fixed_id_, false);
    graph_.setFixed(id, true);
    fixed_id_ = id;
    PoseGraphSolveOptions options;
    options.abort = &abort;
    // The loop shows more drift than the model expects: the odometry edges are that much less
    // certain (a-posteriori scale of the drift model from this loop).
    options.odometry_information_scale = 1.0 / driftScaleFor(d, loop_cov, chain_cov);
    const PoseGraphSolveSummary summary = graph_.optimize(options);
    if (!summary.updated) {
      spdlog::info("loop {} -> {}: pose graph not updated ({})", id, c.keyframe_id,
                   summary.aborted ? "aborted" : "solver failed");
      return std::nullopt;
    }
    out.S_world_camera = graph_.vertices();
    out.time_ms = elapsed();
    spdlog::info(
        "loop closed: keyframe {} -> {} ({} inliers, scale {:.3f}, chi2 {:.1f}, {:.1f} ms)", id,
        c.keyframe_id, out.inliers, out.scale, drift_chi2, out.time_ms);
    return out;
  }
  return std::nullopt;
}

}  // namespace ldsm::loop
