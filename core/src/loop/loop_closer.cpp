#include "loop/loop_closer.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>

namespace ldsm::loop {

LoopCloser::LoopCloser(const LoopConfig& config, const PinholeIntrinsics& camera, bool inline_mode)
    : config_(config), camera_(camera), orb_(camera.width, camera.height) {
  verification_.min_inliers = config.min_inliers;
  LoopTaskOptions options;
  options.mode = inline_mode ? LoopTaskMode::kInline : LoopTaskMode::kThreaded;
  options.queue_capacity = 64;
  task_ = std::make_unique<LoopClosingTask<LoopJob>>(
      [this](LoopJob& job, const std::atomic<bool>& abort) { return process(job, abort); },
      options);
}

LoopCloser::~LoopCloser() {
  task_->stop();
}

void LoopCloser::keyframeLeftWindow(const WindowKeyframe& kf) {
  LoopJob job;
  job.T_w_c = kf.T_c_w.inverse();
  KeyframeFeatures& f = job.features;
  f.keyframe_id = kf.id();
  f.timestamp = kf.timestamp();
  f.camera = camera_;
  orb_.compute(kf.pyramid().intensity(0), kf.corners, f.descriptors, kept_);
  f.pixels.reserve(kept_.size());
  f.idepth.reserve(kept_.size());
  for (const std::uint32_t i : kept_) {
    f.pixels.push_back(kf.corners[i]);
    f.idepth.push_back(i < kf.corner_idepth.size() ? kf.corner_idepth[i] : NAN);
  }
  if (!task_->submit(std::move(job)))
    spdlog::debug("loop closure: queue full, keyframe {} not indexed", kf.id());
}

void LoopCloser::waitIdle() {
  if (!task_->waitIdle(std::chrono::seconds(60)))
    spdlog::warn("loop closure: background task still busy after 60 s");
}

void LoopCloser::addToGraph(const LoopJob& job, bool new_map) {
  const int id = job.features.keyframe_id;
  if (last_id_ >= 0 && graph_.hasVertex(last_id_) && !new_map) {
    // Odometry edge from the window's final relative pose (never from earlier graph results).
    const Sim3d S_prev_cur(last_T_w_c_.inverse() * job.T_w_c);
    graph_.addVertex(id, graph_.vertex(last_id_) * S_prev_cur);
    graph_.addEdge(last_id_, id, S_prev_cur, kDefaultOdometryEdgeWeight,
                   PoseGraphEdgeKind::kOdometry);
  } else {
    graph_.addVertex(id, Sim3d(job.T_w_c));
  }
  last_id_ = id;
  last_T_w_c_ = job.T_w_c;
}

std::optional<LoopCorrection> LoopCloser::process(LoopJob& job, const std::atomic<bool>& abort) {
  const int id = job.features.keyframe_id;
  addToGraph(job, new_map_.exchange(false));
  index_.add(id, job.features.descriptors);
  index_.retrainIfDue(&abort);
  features_[id] = std::move(job.features);
  return closeLoop(id, abort);
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
    // How far the measurement is from what the graph already says, in units of its own
    // uncertainty (Mahalanobis distance squared, 7 DoF, left perturbation of S_current_candidate).
    const double drift_chi2 = loopDisagreementChi2(graph_.vertex(id), graph_.vertex(c.keyframe_id),
                                                   v.S_current_candidate, v.information);
    // Loop edge candidate -> current: S_cand_cur = S_w_cand^-1 S_w_cur.
    graph_.addEdge(c.keyframe_id, id, v.S_current_candidate.inverse(), config_.loop_edge_weight,
                   PoseGraphEdgeKind::kLoop);
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
