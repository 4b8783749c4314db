#include "loop/loop_closer.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include <Eigen/Cholesky>
#include <Eigen/LU>

namespace ldsm::loop {

LoopVerificationSettings loopVerificationSettings(const LoopConfig& config) {
  LoopVerificationSettings s;
  s.min_inliers = config.min_inliers;
  s.min_matches = config.min_matches;
  s.min_matches_with_depth = config.min_pnp_inliers;
  s.pnp.min_inliers = config.min_pnp_inliers;
  return s;
}

LoopCloser::LoopCloser(const LoopConfig& config, const PinholeIntrinsics& camera, bool inline_mode)
    : config_(config), camera_(camera), drift_(OdometryDriftModel::fromConfig(config)) {
  verification_ = loopVerificationSettings(config);
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
  if (task_->stopped()) {
    if (refused_after_stop_.fetch_add(1, std::memory_order_relaxed) == 0)
      spdlog::warn("loop closure: stopped by a timed-out finish; keyframes are not indexed");
    return;
  }
  if (!task_->submit(std::move(kf)))
    spdlog::debug("loop closure: queue full, keyframe {} not indexed", id);
}

void LoopCloser::flush() {
  if (task_->stopped()) return;  // a flush before timed out: nothing runs any more
  using Clock = std::chrono::steady_clock;
  const auto limit = std::chrono::duration_cast<std::chrono::milliseconds>(
      std::chrono::duration<double>(config_.finish_timeout_s));
  const Clock::time_point start = Clock::now();
  // The queue drains first, so the flush job (no keyframe: only the pending pose graph) finds
  // room and is never dropped like a keyframe in a full queue.
  if (task_->waitIdle(limit)) {
    LoopJob flush;
    flush.id = -1;
    task_->submit(std::move(flush));
  }
  const auto left =
      std::max(std::chrono::milliseconds(0),
               limit - std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - start));
  if (const std::uint64_t left_over = task_->finish(left); left_over > 0) {
    spdlog::warn(
        "loop closure: still busy after {} s (loop.finish_timeout_s) at the end of the run; "
        "stopped with {} job(s) unfinished: those keyframes are not looked for loops and a "
        "pending pose-graph correction is not applied; loop closure stays off from here",
        config_.finish_timeout_s, left_over);
  }
}

LoopCloser::GraphExport LoopCloser::exportGraph(
    const std::vector<int>& ids, const std::vector<std::pair<int, Sim3d>>& window) const {
  GraphExport out;
  const auto saved = [&](int id) { return std::find(ids.begin(), ids.end(), id) != ids.end(); };
  for (const PoseGraphEdge& e : graph_.edges())
    if (saved(e.from_id) && saved(e.to_id)) out.edges.push_back(e);
  int prev = last_id_ >= 0 && saved(last_id_) ? last_id_ : -1;
  Sim3d S_prev = prev >= 0 ? graph_.vertex(prev) : Sim3d();
  for (const auto& [id, S_w_c] : window) {
    if (prev >= 0 && !graph_.hasVertex(id)) {
      const Sim3d S_prev_cur = S_prev.inverse() * S_w_c;
      out.edges.push_back(PoseGraphEdge{prev, id, S_prev_cur, drift_.edgeInformation(S_prev_cur),
                                        PoseGraphEdgeKind::kOdometry});
    }
    prev = id;
    S_prev = S_w_c;
  }
  out.vocabulary = index_.sharedVocabulary();
  return out;
}

void LoopCloser::importMap(const std::vector<std::pair<int, Sim3d>>& vertices,
                           const std::vector<PoseGraphEdge>& edges,
                           std::shared_ptr<const Vocabulary> vocabulary,
                           const std::vector<std::shared_ptr<const MarginalizedKeyframe>>& data) {
  ChainPosition chain;
  Sim3d previous;
  bool first = true;
  for (const auto& [id, S_w_c] : vertices) {
    graph_.addVertex(id, S_w_c);
    if (!first)
      chain = {chain.step + 1, chain.path + (S_w_c.translation() - previous.translation()).norm()};
    chain_[id] = chain;
    map_of_[id] = 0;
    previous = S_w_c;
    first = false;
  }
  for (const PoseGraphEdge& e : edges)
    if (graph_.hasVertex(e.from_id) && graph_.hasVertex(e.to_id)) graph_.addEdge(e);
  if (vocabulary) index_.install(std::move(vocabulary), data.size());
  for (const auto& kf : data) {
    if (!kf || !graph_.hasVertex(kf->id)) continue;
    KeyframeFeatures f;
    f.keyframe_id = kf->id;
    f.timestamp = kf->timestamp;
    f.camera = camera_;
    f.pixels = kf->corners;
    f.idepth = kf->corner_idepth;
    f.descriptors = kf->descriptors;
    f.idepth.resize(f.pixels.size(), NAN);
    index_.add(kf->id, f.descriptors);
    features_[kf->id] = std::move(f);
  }
  // The session's first keyframe starts a chain of its own (no odometry edge to the saved map).
  last_id_ = -1;
  chain_base_ = chain.step;
  if (!vertices.empty()) new_map_.store(false);
  place_generation_ = 0;
  publishPlaces(-1);
}

void LoopCloser::forget(int keyframe_id) {
  std::lock_guard<std::mutex> lock(forget_mutex_);
  forget_.push_back(keyframe_id);
}

std::shared_ptr<const PlaceSnapshot> LoopCloser::places() const {
  std::lock_guard<std::mutex> lock(places_mutex_);
  return places_;
}

void LoopCloser::publishPlaces(int id) {
  if (index_.generation() != place_generation_) {
    // A new vocabulary: every keyframe's BoW vector changed.
    place_generation_ = index_.generation();
    place_bows_.clear();
    for (const auto& [kid, f] : features_)
      if (const BowVector* bow = index_.bow(kid))
        place_bows_[kid] = std::make_shared<const BowVector>(*bow);
  } else if (const BowVector* bow = index_.bow(id)) {
    place_bows_[id] = std::make_shared<const BowVector>(*bow);
  } else {
    place_bows_.erase(id);
  }
  auto snapshot = std::make_shared<PlaceSnapshot>();
  snapshot->vocabulary = index_.sharedVocabulary();
  snapshot->keyframes.assign(place_bows_.begin(), place_bows_.end());
  std::lock_guard<std::mutex> lock(places_mutex_);
  places_ = std::move(snapshot);
}

int LoopCloser::heldNeighbour(int candidate) const {
  const auto covisible = covisible_.find(candidate);
  for (const KeyframeLink& l : last_links_) {
    if (!l.map_keyframe || !graph_.hasVertex(l.other)) continue;
    if (l.other == candidate || (covisible != covisible_.end() &&
                                 std::find(covisible->second.begin(), covisible->second.end(),
                                           l.other) != covisible->second.end()))
      return l.other;
  }
  return -1;
}

void LoopCloser::connectCovisible(int a, int b, int shared_points) {
  if (shared_points <= config_.covisible_shared_points) return;
  covisible_[a].push_back(b);
  covisible_[b].push_back(a);
}

Matrix7d LoopCloser::windowEdgeInformation(const Sim3d& S) const {
  // Two keyframes seeing one place may be close together: the translation uncertainty is that of
  // an ordinary step of the chain, not of their (maybe tiny) distance.
  OdometryDriftModel model = drift_;
  if (last_id_ >= 0) {
    const ChainPosition& p = chain_.at(last_id_);
    if (p.step > 0) model.min_step = std::max(model.min_step, p.path / p.step);
  }
  return model.edgeInformation(S);
}

int LoopCloser::addToGraph(const LoopJob& job, bool new_map) {
  const int id = job.id;
  // The vertex is the keyframe's pose in the window: the graph is in the window's frame (a
  // correction holds the newest vertex fixed and never moves the window).
  graph_.addVertex(id, Sim3d(job.T_w_c));
  std::optional<PoseGraphEdge> odometry;
  if (last_id_ >= 0 && graph_.hasVertex(last_id_) && !new_map) {
    // Odometry edge from the window's relative pose, measured in one state of the window: when
    // the previous keyframe left (its link to this one). Without that link (this keyframe was
    // made after it left), from the two poses as they left.
    Sim3d S_prev_cur(last_T_w_c_.inverse() * job.T_w_c);
    for (const KeyframeLink& l : last_links_)
      if (l.other == id) S_prev_cur = Sim3d(l.T_this_other);
    odometry = PoseGraphEdge{last_id_, id, S_prev_cur, drift_.edgeInformation(S_prev_cur),
                             PoseGraphEdgeKind::kOdometry};
    graph_.addEdge(*odometry);
    const ChainPosition& prev = chain_.at(last_id_);
    chain_[id] = {prev.step + 1, prev.path + S_prev_cur.translation().norm()};
  } else {
    // A new map, or the first keyframe after a saved map was loaded: not connected to the
    // earlier chain by any odometry.
    chain_[id] = {(last_id_ >= 0 ? chain_.at(last_id_).step : chain_base_) + kDisconnectedSteps,
                  0.0};
  }
  const bool significant =
      config_.reuse_constraints && addReuseConstraints(job, odometry ? &*odometry : nullptr);
  for (const KeyframeLink& l : job.links) connectCovisible(id, l.other, l.shared_points);
  last_id_ = id;
  last_T_w_c_ = job.T_w_c;
  last_links_ = job.links;
  return significant ? 1 : 0;
}

bool LoopCloser::addReuseConstraints(const LoopJob& job, const PoseGraphEdge* odometry) {
  bool any = false;
  for (const KeyframeLink& l : job.links) {
    if (!l.map_keyframe || !graph_.hasVertex(l.other) || l.other == job.id) continue;
    // The map keyframe was held at its map pose and scale in the window.
    Sim3d S_cur_map(l.T_this_other);
    S_cur_map.setScale(graph_.vertex(l.other).scale());
    graph_.addEdge(PoseGraphEdge{job.id, l.other, S_cur_map, windowEdgeInformation(S_cur_map),
                                 PoseGraphEdgeKind::kReuse});
    any = true;
  }
  if (!any || !odometry) return false;
  // The keyframe is where the map keyframe says (its vertex is its window pose); when the window
  // moved onto the map after the previous keyframe left, the odometry edge carries that jump:
  // the drift the revisit revealed, which the pose graph spreads over the keyframes in between.
  const Vector7d r = graph_.edgeResidual(*odometry);
  const double chi2 = r.dot(windowEdgeInformation(odometry->S_from_to) * r);
  spdlog::debug("loop closure: keyframe {} tied to the map, odometry disagreement chi2 {:.1f}",
                job.id, chi2);
  return chi2 >= config_.correction_chi2;
}

void LoopCloser::markPending() {
  if (pending_first_ < 0) pending_first_ = processed_;
  pending_last_ = processed_;
}

bool LoopCloser::poseGraphDue() const {
  if (pending_first_ < 0) return false;
  // Keyframes processed since the one that brought the newest (first) constraint.
  const int since_last = processed_ - 1 - pending_last_;
  const int since_first = processed_ - 1 - pending_first_;
  return since_last >= config_.pose_graph_delay_keyframes ||
         since_first >= config_.pose_graph_max_delay_keyframes;
}

std::optional<LoopCorrection> LoopCloser::process(LoopJob& job, const std::atomic<bool>& abort) {
  LoopCorrection out;
  if (job.id < 0) {
    // Flush: the pending pose graph now.
    if (pending_first_ >= 0) optimizePending(out, abort);
    out.folded.swap(folded_);
    if (out.loops.empty() && out.S_world_camera.empty() && out.folded.empty()) return std::nullopt;
    return out;
  }
  const int id = job.id;
  std::vector<int> forget;
  {
    std::lock_guard<std::mutex> lock(forget_mutex_);
    forget.swap(forget_);
  }
  for (const int k : forget) {
    index_.remove(k);
    features_.erase(k);
    place_bows_.erase(k);
    retired_.emplace_back(k, processed_);
  }
  const bool new_map = new_map_.exchange(false);
  // A new map is not connected to the old one: what the old map still waits for is solved now,
  // while its newest keyframe can hold the gauge.
  if (new_map && pending_first_ >= 0) optimizePending(out, abort);
  if (new_map) map_parent_.push_back(static_cast<int>(map_parent_.size()));
  map_of_[id] = static_cast<int>(map_parent_.size()) - 1;
  const int reuse = addToGraph(job, new_map);
  if (reuse > 0) {
    pending_reuse_ += reuse;
    markPending();
  }
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
  if (std::optional<DetectedLoop> loop = closeLoop(id, out.merge)) {
    if (loop->significant) {
      pending_loops_.push_back(*loop);
      markPending();
    } else {
      out.loops.push_back(*loop);
    }
  }
  if (job.culled) {
    // Redundant with the map: it looks for loops, but is no place to be found itself.
    index_.remove(id);
    features_.erase(id);
    retired_.emplace_back(id, processed_);
  }
  publishPlaces(id);
  ++processed_;
  if (poseGraphDue()) optimizePending(out, abort);
  foldRetired();
  graph_vertices_.store(static_cast<std::int64_t>(graph_.numVertices()), std::memory_order_relaxed);
  graph_edges_.store(static_cast<std::int64_t>(graph_.edges().size()), std::memory_order_relaxed);
  // Folds go out with the next correction (the map store needs them only when keyframes move),
  // or on their own once a few have gathered.
  constexpr std::size_t kPublishFolds = 64;
  const bool moves = !out.S_world_camera.empty() || out.merge;
  if (!folded_.empty() && (moves || folded_.size() >= kPublishFolds)) out.folded.swap(folded_);
  if (out.loops.empty() && !moves && out.folded.empty()) return std::nullopt;
  return out;
}

int LoopCloser::foldAnchor(int id) const {
  // The neighbour it is tied to most firmly (usually a map keyframe at the same place, from the
  // window): the rerouted edges gain the least uncertainty, and the keyframe's pose, which then
  // follows that neighbour rigidly, the shortest lever arm.
  int best = -1;
  double best_certainty = -std::numeric_limits<double>::infinity();
  for (const PoseGraphEdge& e : graph_.edges()) {
    if (e.from_id != id && e.to_id != id) continue;
    const double certainty = informationLogDet(e.information);
    if (certainty > best_certainty) {
      best_certainty = certainty;
      best = e.from_id == id ? e.to_id : e.from_id;
    }
  }
  return best;
}

void LoopCloser::foldRetired() {
  std::vector<std::pair<int, int>> keep;
  for (const auto& [id, retired_at] : retired_) {
    if (id == last_id_ || processed_ - retired_at < config_.pose_graph_recent_keyframes) {
      keep.emplace_back(id, retired_at);
      continue;
    }
    if (!graph_.hasVertex(id)) continue;
    const int anchor = foldAnchor(id);
    if (anchor < 0) {
      graph_.removeIsolatedVertex(id);
    } else {
      const int rerouted = graph_.foldVertex(id, anchor);
      folded_.emplace_back(id, anchor);
      spdlog::debug("pose graph: keyframe {} folded into {} ({} edges rerouted)", id, anchor,
                    rerouted);
    }
    fixed_ids_.erase(std::remove(fixed_ids_.begin(), fixed_ids_.end(), id), fixed_ids_.end());
    chain_.erase(id);
    map_of_.erase(id);
    const auto it = covisible_.find(id);
    if (it != covisible_.end()) {
      for (const int other : it->second) {
        auto o = covisible_.find(other);
        if (o == covisible_.end()) continue;
        o->second.erase(std::remove(o->second.begin(), o->second.end(), id), o->second.end());
      }
      covisible_.erase(it);
    }
  }
  retired_.swap(keep);
}

void LoopCloser::optimizePending(LoopCorrection& out, const std::atomic<bool>& abort) {
  const auto t0 = std::chrono::steady_clock::now();
  for (const int id : fixed_ids_)
    if (graph_.hasVertex(id)) graph_.setFixed(id, false);
  fixed_ids_.assign(1, last_id_);
  // The map keyframes the window held with the newest keyframe keep their poses too
  // (LoopClosureConfig::hold_reused_keyframes): the correction moves the rest of the map.
  if (config_.hold_reused_keyframes)
    for (const KeyframeLink& l : last_links_)
      if (l.map_keyframe && l.other != last_id_ && graph_.hasVertex(l.other))
        fixed_ids_.push_back(l.other);
  for (const int id : fixed_ids_) graph_.setFixed(id, true);
  PoseGraphSolveOptions options;
  options.abort = &abort;
  // A loop that shows more drift than the model expects: the odometry edges are that much less
  // certain (a-posteriori scale of the drift model from the largest such loop).
  for (const DetectedLoop& l : pending_loops_)
    options.odometry_information_scale =
        std::min(options.odometry_information_scale, 1.0 / l.drift_scale);
  const PoseGraphSolveSummary summary = graph_.optimize(options);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (summary.updated) {
    out.S_world_camera = graph_.vertices();
    out.reuse_constraints = pending_reuse_;
    spdlog::info(
        "pose graph: {} loop(s) and {} constraint(s) from map reuse, {} keyframes corrected "
        "({:.1f} ms)",
        pending_loops_.size(), pending_reuse_, out.S_world_camera.size(), ms);
  } else {
    spdlog::info("pose graph not updated ({})", summary.aborted ? "aborted" : "solver failed");
  }
  for (DetectedLoop& l : pending_loops_) {
    l.time_ms += ms;
    out.loops.push_back(l);
  }
  pending_loops_.clear();
  pending_reuse_ = 0;
  pending_first_ = pending_last_ = -1;
}

int LoopCloser::mapRoot(int map) const {
  while (map >= 0 && map < static_cast<int>(map_parent_.size()) && map_parent_[map] != map)
    map = map_parent_[map];
  return map;
}

MapMerge LoopCloser::mergeMaps(int id, int candidate, const Sim3d& S_current_candidate) {
  MapMerge m;
  m.from_map = mapRoot(map_of_.at(candidate));
  m.into_map = mapRoot(map_of_.at(id));
  m.current_keyframe_id = id;
  m.candidate_keyframe_id = candidate;
  m.S_into_from = graph_.vertex(id) * S_current_candidate * graph_.vertex(candidate).inverse();
  // The earlier map's chain continues from here: the candidate sits where the current keyframe
  // is (for the drift the chain may accumulate between the two maps' keyframes).
  const ChainPosition anchor = chain_.at(candidate);
  const ChainPosition here = chain_.at(id);
  for (const auto& [k, map] : map_of_) {
    if (mapRoot(map) != m.from_map || !graph_.hasVertex(k)) continue;
    const Sim3d moved = m.S_into_from * graph_.vertex(k);
    graph_.setVertex(k, moved);
    m.S_world_camera[k] = moved;
    ChainPosition& c = chain_.at(k);
    c = {here.step + (c.step - anchor.step), here.path + (c.path - anchor.path)};
  }
  map_parent_[static_cast<std::size_t>(m.from_map)] = m.into_map;
  spdlog::info("loop closure: map {} merged into map {} (keyframe {} -> {}, scale {:.3f})",
               m.from_map, m.into_map, id, candidate, m.S_into_from.scale());
  return m;
}

std::optional<DetectedLoop> LoopCloser::closeLoop(int id, std::optional<MapMerge>& merge) {
  const auto t0 = std::chrono::steady_clock::now();
  const int recent = config_.exclude_recent_keyframes;
  const auto covisible = covisible_.find(id);
  auto connected = [&](int k) {
    if (k >= id - recent) return true;  // the `recent` keyframes right before id
    return covisible != covisible_.end() &&
           std::find(covisible->second.begin(), covisible->second.end(), k) !=
               covisible->second.end();
  };
  const std::vector<PlaceCandidate> candidates =
      index_.query(id, connected, config_.max_candidates);
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
    if (mapRoot(map_of_.at(id)) != mapRoot(map_of_.at(c.keyframe_id))) {
      // Two maps: no trajectory connects them yet; the loop makes them one.
      merge = mergeMaps(id, c.keyframe_id, v.S_current_candidate);
      graph_.addEdge(PoseGraphEdge{c.keyframe_id, id, v.S_current_candidate.inverse(),
                                   v.information, PoseGraphEdgeKind::kLoop});
      DetectedLoop out;
      out.current_keyframe_id = id;
      out.candidate_keyframe_id = c.keyframe_id;
      out.inliers = v.num_inliers;
      out.scale = v.S_current_candidate.scale();
      out.time_ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      return out;
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
    const int held = heldNeighbour(c.keyframe_id);
    if (held >= 0) {
      // The window held map keyframe `held` with this keyframe, and the candidate is that
      // keyframe or was optimised in one window with it: two window edges relate it to this
      // keyframe, with no chain of odometry in between that could have drifted. A loop that
      // disagrees with them is a wrong measurement, not drift to correct.
      const double path =
          (graph_.vertex(id).translation() - graph_.vertex(held).translation()).norm() +
          (graph_.vertex(held).translation() - graph_.vertex(c.keyframe_id).translation()).norm();
      const int steps = held == c.keyframe_id ? 1 : 2;
      const Matrix7d held_cov = drift_.chainCovariance(steps, path, implied);
      const double chi2 = d.dot(Eigen::LDLT<Matrix7d>(loop_cov + held_cov).solve(d));
      if (chi2 >= config_.correction_chi2) {
        spdlog::debug(
            "loop {} -> {} (score {:.3f}) rejected: disagrees with map keyframe {} the window held "
            "(chi2 {:.1f}, {} inliers)",
            id, c.keyframe_id, c.score, held, chi2, v.num_inliers);
        continue;
      }
    }
    // Loop edge candidate -> current: S_cand_cur = S_w_cand^-1 S_w_cur; its residual is the
    // loop's own tangent error, so the edge takes the loop's information as it is.
    graph_.addEdge(PoseGraphEdge{c.keyframe_id, id, v.S_current_candidate.inverse(), v.information,
                                 PoseGraphEdgeKind::kLoop});
    DetectedLoop out;
    out.current_keyframe_id = id;
    out.candidate_keyframe_id = c.keyframe_id;
    out.inliers = v.num_inliers;
    out.scale = v.S_current_candidate.scale();
    out.drift_chi2 = d.dot(Eigen::LDLT<Matrix7d>(loop_cov + chain_cov).solve(d));
    // Below the threshold the odometry already agrees with the loop within the loop's own
    // accuracy: a correction would only move the trajectory by the measurement's noise. The
    // edge stays in the graph for later corrections.
    out.significant = out.drift_chi2 >= config_.correction_chi2;
    out.drift_scale = out.significant ? driftScaleFor(d, loop_cov, chain_cov) : 1.0;
    out.time_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    spdlog::info("loop found: keyframe {} -> {} ({} inliers, scale {:.3f}, chi2 {:.1f}){}", id,
                 c.keyframe_id, out.inliers, out.scale, out.drift_chi2,
                 out.significant ? ": drift, the pose graph corrects it"
                                 : ": drift not significant, nothing to correct");
    return out;
  }
  return std::nullopt;
}

}  // namespace ldsm::loop
