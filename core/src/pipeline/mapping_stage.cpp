#include "pipeline/mapping_stage.h"

#include <spdlog/spdlog.h>

#include "backend/reference_budget.h"
#include "concurrency/backoff.h"
#include "math/constants.h"
#include "reuse/redundancy.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ldsm {
namespace {

CalibrationStats calibrationStats(const Mapper& mapper) {
  const CalibrationRefinement& r = mapper.calibration();
  CalibrationStats c;
  c.configured = mapper.baseCamera().intrinsics();
  c.applied = mapper.camera().intrinsics();
  c.radial_applied = r.applied()[kCalibRadial];
  c.radial_estimate = r.estimate()[kCalibRadial];
  c.focal_scale_estimate = std::exp(r.estimate()[kCalibFocal]);
  c.cx_shift_estimate = r.estimate()[kCalibCx];
  c.cy_shift_estimate = r.estimate()[kCalibCy];
  const CalibVector sigma = r.sigma();
  c.radial_sigma = sigma[kCalibRadial];
  c.focal_scale_sigma = sigma[kCalibFocal];
  c.cx_sigma = sigma[kCalibCx];
  c.cy_sigma = sigma[kCalibCy];
  const CalibVector realistic = r.realisticSigma();
  c.realistic_radial_sigma = realistic[kCalibRadial];
  c.realistic_focal_scale_sigma = realistic[kCalibFocal];
  c.realistic_cx_sigma = realistic[kCalibCx];
  c.realistic_cy_sigma = realistic[kCalibCy];
  c.windows = r.windows();
  return c;
}

CalibrationSample calibrationSample(const CalibrationStats& c, const WindowKeyframe& newest) {
  CalibrationSample sample;
  sample.windows = c.windows;
  sample.frame_index = newest.frameIndex();
  sample.timestamp = newest.timestamp();
  sample.radial_estimate = c.radial_estimate;
  sample.focal_scale_estimate = c.focal_scale_estimate;
  sample.cx_shift_estimate = c.cx_shift_estimate;
  sample.cy_shift_estimate = c.cy_shift_estimate;
  sample.radial_sigma = c.radial_sigma;
  sample.focal_scale_sigma = c.focal_scale_sigma;
  sample.cx_sigma = c.cx_sigma;
  sample.cy_sigma = c.cy_sigma;
  sample.realistic_radial_sigma = c.realistic_radial_sigma;
  sample.realistic_focal_scale_sigma = c.realistic_focal_scale_sigma;
  sample.realistic_cx_sigma = c.realistic_cx_sigma;
  sample.realistic_cy_sigma = c.realistic_cy_sigma;
  sample.radial_applied = c.radial_applied;
  sample.applied = c.applied;
  return sample;
}

}  // namespace

MappingStage::MappingStage(const MappingStageSettings& settings, const PyramidCamera& camera,
                           PyramidPool& pyramids, MapStore& store, EventSink& events,
                           loop::LoopCloser* loop_closer, bool inline_mode)
    : settings_(settings),
      pyramids_(pyramids),
      store_(store),
      events_(events),
      loop_closer_(loop_closer),
      mapper_(settings.mapper, camera, pyramids),
      references_([camera, tracker = settings.tracker] {
        return std::make_unique<CoarseTracker>(camera[0].width, camera[0].height, camera.levels(),
                                               tracker);
      }),
      depth_canvas_(camera[0].width, camera[0].height, camera.levels()),
      timer_({"trace", "mapping", "reuse", "loop"}, StageTimer::kPipelineSamples),
      describe_(loop_closer != nullptr || settings.reuse.enabled),
      inline_mode_(inline_mode),
      snapshot_(std::make_shared<const MappingSnapshot>()) {
  mapper_.setDescribeLeavingKeyframes(
      describe_,
      PixelSelector::CornerLimits{settings.loop_corners, settings.loop_corner_min_score});
  if (describe_) orb_ = std::make_unique<OrbExtractor>(camera[0].width, camera[0].height);
  if (settings.parallel_threads > 1) {
    parallel_ = std::make_unique<concurrency::ParallelTasks>(settings.parallel_threads);
    mapper_.setParallelTasks(parallel_.get());
  }
  if (settings.reuse.enabled) {
    reuse_ = std::make_unique<ReactivationSearch>(settings.reuse);
    resting_ = RestingKeyframes(settings.reuse.rest_keyframes);
    mapper_.setCoverageRadius(static_cast<float>(settings.reuse.coverage_radius_px));
    reference_point_budget_ = referencePointBudget(settings.reuse.reference_point_ratio,
                                                   settings.mapper.window.active_points);
  }
  depth_points_.reserve(64 * 1024);
  concurrency::TaskOptions options;
  options.mode = inline_mode ? concurrency::TaskMode::kInline : concurrency::TaskMode::kThreaded;
  options.queue_capacity = static_cast<std::size_t>(settings.queue_capacity);
  options.wait_when_full = true;
  options.priority = concurrency::WorkerPriority::kNormal;
  task_ = std::make_unique<concurrency::BackgroundTask<MappingJob, Done>>(
      [this](MappingJob& job, const std::atomic<bool>&) { return process(job); }, options);
}

MappingStage::~MappingStage() {
  task_->stop();
}

void MappingStage::submit(MappingJob job) {
  // The tracking thread never waits for room for an ordinary frame: its tracing is skipped when
  // the queue is full (as trace() skips it when the mapping thread is behind).
  if (job.kind == MappingJob::Kind::kTrace &&
      task_->backlog() >= static_cast<std::size_t>(std::max(settings_.queue_capacity, 1)) &&
      !inline_mode_) {
    pyramids_.release(std::move(job.pyramid));
    return;
  }
  task_->submit(std::move(job));
}

void MappingStage::waitIdle() {
  while (!task_->waitIdle(std::chrono::seconds(10)))
    spdlog::debug("mapping: still busy, {} jobs queued", task_->backlog());
}

void MappingStage::waitForKeyframe() {
  for (concurrency::Backoff backoff; keyframeInFlight(); backoff.pause()) {
  }
}

std::optional<MappingStage::Done> MappingStage::process(MappingJob& job) {
  try {
    switch (job.kind) {
      case MappingJob::Kind::kTrace:
        trace(job);
        break;
      case MappingJob::Kind::kKeyframe:
        integrateKeyframe(job);
        break;
      case MappingJob::Kind::kInitialize:
        initialize(job);
        break;
      case MappingJob::Kind::kReset:
        reset();
        break;
      case MappingJob::Kind::kRelocalize:
        relocalize(job);
        break;
      case MappingJob::Kind::kNewMap:
        // Relocalisation gave up: what follows is a new map, not chained to the old one.
        if (loop_closer_) loop_closer_->startNewMap();
        store_.startNewMap();
        ++reuse_stats_.new_maps;
        break;
    }
  } catch (const std::exception& e) {
    spdlog::error("mapping failed on frame {}: {}", job.info.frame_index, e.what());
    keyframe_in_flight_.store(false, std::memory_order_release);
  }
  pyramids_.release(std::move(job.pyramid));
  pyramids_.release(std::move(job.reference_pyramid));
  return std::nullopt;
}

void MappingStage::trace(MappingJob& job) {
  // Behind (threaded mode): skip the tracing of ordinary frames until the queue is short again.
  if (task_->backlog() > 1) return;
  StageTimer::Scope t(timer_, kTrace);
  mapper_.traceFrame(*job.pyramid, job.info);
}

void MappingStage::integrateKeyframe(MappingJob& job) {
  {
    StageTimer::Scope t(timer_, kTrace);
    mapper_.traceFrame(*job.pyramid, job.info);
  }
  StageTimer::Scope t(timer_, kMapping);
  KeyframeInsertion ins = mapper_.addKeyframe(std::move(job.pyramid), job.info);
  keyframes_.fetch_add(1, std::memory_order_relaxed);
  reuse_stats_.map_points_seen += ins.map_points_in_view;
  publishMap(std::move(ins.map));
  applyLoopCorrections();
  if (reuse_) {
    StageTimer::Scope r(timer_, kReuse);
    reuseMap(job.info.frame_index, job.info.timestamp);
  }
  publishReference();
  mapper_.compactNewestImage();  // the tracker and the reuse view have what they need of it
  publishSnapshot();
  keyframe_in_flight_.store(false, std::memory_order_release);
  const WindowKeyframe& newest = mapper_.newestKeyframe();
  events_.keyframe(KeyframeEvent{newest.id(), job.info.frame_index, job.info.timestamp,
                                 newest.T_c_w.inverse().toPose(), ins.active_points});
  spdlog::debug(
      "keyframe {} (frame {}): {} active, {} activated, {} marginalised, rmse {:.2f}, "
      "{} left the view",
      newest.id(), job.info.frame_index, ins.active_points, ins.activated_points,
      ins.marginalized_frames, ins.optimization.rmse, ins.retired_points);
}

void MappingStage::initialize(MappingJob& job) {
  KeyframeInsertion ins;
  const bool ok =
      mapper_.initialize(job.initialization, job.reference_info, std::move(job.reference_pyramid),
                         job.info, std::move(job.pyramid), &ins);
  publishMap(std::move(ins.map));
  init_outcome_ = InitializationOutcome();
  if (!ok) return;
  keyframes_.fetch_add(2, std::memory_order_relaxed);
  startWindow(job.info, mapper_.activePointCount(), /*initialized=*/true);
  spdlog::info("frame {}: initialised with {} points", job.info.frame_index, init_outcome_.points);
}

void MappingStage::relocalize(MappingJob& job) {
  init_outcome_ = InitializationOutcome();
  const std::shared_ptr<const MarginalizedKeyframe> anchor =
      store_.keyframeData(job.anchor_keyframe);
  const KeyframeRecord pose = store_.keyframe(job.anchor_keyframe);
  if (!anchor || pose.id < 0) return;
  KeyframeInsertion ins =
      mapper_.relocalize(std::move(job.pyramid), job.info, *anchor, pose.T_w_c, pose.scale);
  publishMap(std::move(ins.map));
  keyframes_.fetch_add(1, std::memory_order_relaxed);
  ++reuse_stats_.reactivations;
  if (!settings_.localize_only) store_.connect(mapper_.newestKeyframe().id(), job.anchor_keyframe);
  last_on_map_id_ = mapper_.newestKeyframe().id();
  startWindow(job.info, ins.map_points_in_view, /*initialized=*/false);
}

void MappingStage::startWindow(const MapperFrame& info, int points, bool initialized) {
  const WindowKeyframe& newest = mapper_.newestKeyframe();
  init_outcome_ = {true, points, newest.id(), newest.T_c_w, newest.aff};
  publishReference();
  mapper_.compactNewestImage();
  publishSnapshot();
  if (initialized) events_.initialized(InitializedEvent{info.frame_index, info.timestamp, points});
  events_.keyframe(KeyframeEvent{newest.id(), info.frame_index, info.timestamp,
                                 newest.T_c_w.inverse().toPose(), points});
}

void MappingStage::continueAfterLoadedMap(int next_keyframe_id, const MapCalibration& calibration,
                                          std::optional<double> median_depth) {
  mapper_.setNextKeyframeId(next_keyframe_id);
  if (median_depth && *median_depth > 0.0 && std::isfinite(*median_depth)) {
    median_depth_ = *median_depth;
    spdlog::debug("loaded map: median depth {:.4g} map units", median_depth_);
  }
  mapper_.startCalibrationAt(calibration.focal_log_scale, calibration.cx_shift,
                             calibration.cy_shift);
  publishSnapshot();
}

void MappingStage::reset() {
  reanchor_.publish(ReanchorRequest());  // (none: a window that no longer exists drifted)
  publishMap(mapper_.reset());
  window_descriptions_.clear();
  last_left_id_ = -1;
  references_.clear();
  keyframe_in_flight_.store(false, std::memory_order_release);
  publishSnapshot();
}

void MappingStage::publishMap(MapUpdate&& update) {
  store_.setKeyframes(update.keyframes);
  store_.retireFrames();  // beyond system.frame_history (none by default offline)
  // Localising only: the loaded map is never changed (what leaves the window is dropped).
  if (settings_.localize_only) return;
  store_.addPoints(update.points);
  for (MarginalizedKeyframe& kf : update.left) {
    if (describe_) describeOrb(kf);
    // A keyframe an earlier visit's map keyframe already covers adds nothing the map lacks.
    if (reuse_ && settings_.reuse.cull_redundant) {
      const RedundancyCheck r =
          checkRedundancy(kf, store_.keyframe(kf.id), store_, mapper_.camera()[0], settings_.reuse);
      kf.culled = r.redundant;
      if (r.redundant)
        spdlog::trace("reuse: keyframe {} is covered by map keyframe {} ({:.0f} %)", kf.id,
                      r.covered_by, 100.0 * r.coverage);
      else
        spdlog::debug("reuse: keyframe {} joins the map (best cover {:.0f} % by keyframe {})",
                      kf.id, 100.0 * r.coverage, r.covered_by);
    }
    if (kf.culled) {
      store_.cullKeyframe(kf.id);
      ++reuse_stats_.culled_keyframes;
    } else if (reuse_) {
      store_.setKeyframeData(std::make_shared<MarginalizedKeyframe>(asMapKeyframe(kf)));
      if (last_left_id_ >= 0) store_.connect(last_left_id_, kf.id);
      last_left_id_ = kf.id;
    }
    if (loop_closer_) {
      kf.points.clear();  // loop closure needs the corners only
      StageTimer::Scope l(timer_, kLoop);
      loop_closer_->keyframeLeftWindow(std::move(kf));
    }
  }
  if (reuse_ && settings_.reuse.max_map_keyframes > 0) keepMapBudget();
}

MarginalizedKeyframe MappingStage::asMapKeyframe(const MarginalizedKeyframe& kf) const {
  MarginalizedKeyframe data = kf;
  // Only points the window measured from several keyframes: a keyframe marginalised soon after
  // it was made hosts many points seen once, whose depths are guesses.
  auto& pts = data.points;
  pts.erase(std::remove_if(pts.begin(), pts.end(),
                           [&](const PatchPoint& p) {
                             return p.observations < settings_.reuse.min_point_observations;
                           }),
            pts.end());
  // The map store keeps this keyframe for the whole run: no room for the points left out.
  pts.shrink_to_fit();
  return data;
}

std::vector<MarginalizedKeyframe> MappingStage::windowForMap() {
  std::vector<MarginalizedKeyframe> out;
  if (!mapper_.initialized()) return out;
  for (MarginalizedKeyframe& kf : mapper_.describeWindow()) {
    if (describe_) describeOrb(kf);
    kf.image = ImageF();
    out.push_back(asMapKeyframe(kf));
  }
  return out;
}

void MappingStage::keepMapBudget() {
  const double angle = radians(settings_.reuse.redundancy_angle_deg);
  const std::vector<int> in_window = mapper_.reactivatedIds();
  while (static_cast<int>(store_.dataKeyframeCount()) > settings_.reuse.max_map_keyframes) {
    const int victim = store_.mostRedundantKeyframe(angle, in_window);
    if (victim < 0) break;
    store_.cullKeyframe(victim);
    ++reuse_stats_.culled_keyframes;
    if (loop_closer_) loop_closer_->forget(victim);
  }
}

void MappingStage::describeOrb(MarginalizedKeyframe& kf) {
  if (kf.image.empty()) return;
  const auto made = std::find_if(window_descriptions_.begin(), window_descriptions_.end(),
                                 [&](const OrbDescription& d) { return d.keyframe_id == kf.id; });
  if (made != window_descriptions_.end() && made->corners == kf.corners) {
    kf.descriptors = std::move(made->descriptors);
    orb_kept_ = std::move(made->kept);
  } else {
    orb_->compute(kf.image.view(), kf.corners, kf.descriptors, orb_kept_);
  }
  if (made != window_descriptions_.end()) window_descriptions_.erase(made);
  std::vector<Eigen::Vector2f> corners;
  std::vector<float> idepth;
  corners.reserve(orb_kept_.size());
  idepth.reserve(orb_kept_.size());
  for (const std::uint32_t i : orb_kept_) {
    corners.push_back(kf.corners[i]);
    idepth.push_back(i < kf.corner_idepth.size() ? kf.corner_idepth[i]
                                                 : std::numeric_limits<float>::quiet_NaN());
  }
  kf.corners = std::move(corners);
  kf.corner_idepth = std::move(idepth);
  kf.image = ImageF();
}

/// The median depth of non-empty `points` (scratch: reused storage for their inverse depths).
double MappingStage::medianDepth(const std::vector<DepthPoint>& points,
                                 std::vector<float>& scratch) {
  scratch.clear();
  for (const DepthPoint& p : points) scratch.push_back(p.idepth);
  const auto mid = scratch.begin() + static_cast<std::ptrdiff_t>(scratch.size() / 2);
  std::nth_element(scratch.begin(), mid, scratch.end());
  return 1.0 / std::max(1e-6f, *mid);
}

void MappingStage::applyLoopCorrections() {
  if (loop_closer_) applyCorrections(loop_closer_->takeCorrections());
}

void MappingStage::applyCorrections(const std::vector<loop::LoopCorrection>& corrections) {
  for (const loop::LoopCorrection& c : corrections) {
    store_.followKeyframes(c.folded);
    int merged = 0;
    if (c.merge) merged = mergeMaps(*c.merge);
    int moved = 0;
    if (!c.S_world_camera.empty()) {
      // Reactivated keyframes are held at their map poses: they move with the map.
      std::vector<KeyframeRecord> held;
      for (const int id : mapper_.reactivatedIds()) held.push_back(store_.keyframe(id));
      moved = store_.applyCorrection(c.S_world_camera);
      for (const KeyframeRecord& before : held) {
        if (before.id < 0) continue;
        const KeyframeRecord after = store_.keyframe(before.id);
        mapper_.moveReactivated(after.id, after.T_w_c, after.scale / before.scale);
      }
      if (c.reuse_constraints > 0) ++reuse_stats_.map_corrections;
    }
    for (const loop::DetectedLoop& l : c.loops) {
      LoopClosureEvent e;
      e.current_keyframe_id = l.current_keyframe_id;
      e.matched_keyframe_id = l.candidate_keyframe_id;
      e.inliers = l.inliers;
      e.scale = l.scale;
      e.time_ms = l.time_ms;
      e.drift_chi2 = l.drift_chi2;
      e.corrected_keyframes = l.significant ? moved : 0;
      if (c.merge && c.merge->current_keyframe_id == l.current_keyframe_id &&
          c.merge->candidate_keyframe_id == l.candidate_keyframe_id)
        e.corrected_keyframes = merged;
      store_.connect(l.current_keyframe_id, l.candidate_keyframe_id);
      events_.loopClosed(e);
    }
  }
}

int MappingStage::mergeMaps(const loop::MapMerge& m) {
  // The earlier map comes into the window's frame; map keyframes of it in the window (none
  // normally: reuse looks in the current map) would carry their old poses.
  for (const int id : mapper_.reactivatedIds())
    if (m.S_world_camera.count(id) != 0) mapper_.deactivate(id);
  const int moved = store_.mergeMaps(m.from_map, m.into_map, m.S_into_from, m.S_world_camera);
  ++reuse_stats_.merges;
  MapMergeEvent e;
  e.merged_map = m.from_map;
  e.into_map = m.into_map;
  e.current_keyframe_id = m.current_keyframe_id;
  e.matched_keyframe_id = m.candidate_keyframe_id;
  e.scale = m.S_into_from.scale();
  e.moved_keyframes = moved;
  e.in_map_frame = store_.inFirstMap(m.into_map);
  events_.mapsMerged(e);
  return moved;
}

void MappingStage::publishReference() {
  mapper_.trackingPoints(depth_points_);
  if (!depth_points_.empty()) median_depth_ = medianDepth(depth_points_, idepths_);
  thinToReferenceBudget(depth_points_, reference_point_budget_);
  std::unique_ptr<CoarseTracker> tracker = references_.acquire();
  const TrackingReference r = mapper_.newestReference();
  tracker->setReference(*r.pyramid, mapper_.camera(), depth_points_, r.exposure, r.aff,
                        &depth_canvas_, mapper_.radialK());
  references_.publish({std::move(tracker), r.keyframe_id, r.T_c_w, r.frame_index,
                       mapper_.calibration().settling()});
}

void MappingStage::publishSnapshot() {
  auto s = std::make_shared<MappingSnapshot>();
  s->has_window = mapper_.initialized();
  if (s->has_window) {
    s->active_points = mapper_.activeMapPoints();
    s->newest_T_c_w = mapper_.newestKeyframe().T_c_w;
    for (const KeyframeRecord& r : mapper_.windowPoses()) s->window_ids.push_back(r.id);
  } else {
    s->newest_T_c_w = snapshot()->newest_T_c_w;  // where the camera was last seen
    s->window_ids = snapshot()->window_ids;
  }
  s->median_depth = median_depth_;
  s->active_point_count = static_cast<int>(s->active_points.size());
  s->radial_estimate = mapper_.radialEstimate();
  s->radial_applied = mapper_.radialK();
  s->calibration_applied = mapper_.calibration().applied();
  s->calibration = calibrationStats(mapper_);
  if (s->has_window && s->calibration.windows > 0)
    calibration_history_.add(calibrationSample(s->calibration, mapper_.newestKeyframe()));
  s->calibration_history = calibration_history_.samples();
  s->reactivated = mapper_.reactivatedIds();
  s->reuse = reuse_stats_;
  std::lock_guard<std::mutex> lock(snapshot_mutex_);
  snapshot_ = std::move(s);
}

std::shared_ptr<const MappingSnapshot> MappingStage::snapshot() const {
  std::lock_guard<std::mutex> lock(snapshot_mutex_);
  return snapshot_;
}

void MappingStage::finish() {
  waitIdle();
  // The mapping thread is idle: the window may be read and the loop corrections applied here.
  if (loop_closer_) {
    loop_closer_->flush();
    applyLoopCorrections();
  }
  if (mapper_.initialized()) {
    MapUpdate update;
    update.keyframes = mapper_.windowPoses();
    publishMap(std::move(update));
  }
  publishSnapshot();
}

}  // namespace ldsm
