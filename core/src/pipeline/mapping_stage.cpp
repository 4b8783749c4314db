#include "pipeline/mapping_stage.h"

#include <spdlog/spdlog.h>

#include "concurrency/backoff.h"

namespace ldsm {

MappingStage::MappingStage(const Config& config, const PyramidCamera& camera, PyramidPool& pyramids,
                           MapStore& store, EventSink& events, loop::LoopCloser* loop_closer,
                           bool photometry_known, bool inline_mode)
    : config_(config),
      camera_(camera),
      pyramids_(pyramids),
      store_(store),
      events_(events),
      loop_closer_(loop_closer),
      mapper_(MapperSettings::fromConfig(config, photometry_known), camera, pyramids),
      references_([camera, settings = CoarseTrackerSettings::fromConfig(config, photometry_known)] {
        return std::make_unique<CoarseTracker>(camera[0].width, camera[0].height, camera.levels(),
                                               settings);
      }),
      timer_({"trace", "mapping"}, 20000),
      snapshot_(std::make_shared<const MappingSnapshot>()) {
  mapper_.setDescribeLeavingKeyframes(loop_closer_ != nullptr);
  depth_points_.reserve(64 * 1024);
  concurrency::TaskOptions options;
  options.mode = inline_mode ? concurrency::TaskMode::kInline : concurrency::TaskMode::kThreaded;
  options.queue_capacity = static_cast<std::size_t>(config.system.mapping_queue);
  options.wait_when_full = true;
  options.priority = concurrency::WorkerPriority::kNormal;
  task_ = std::make_unique<concurrency::BackgroundTask<MappingJob, Done>>(
      [this](MappingJob& job, const std::atomic<bool>&) { return process(job); }, options);
}

MappingStage::~MappingStage() {
  task_->stop();
}

void MappingStage::submit(MappingJob job) {
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
  publishMap(std::move(ins.map));
  applyLoopCorrections();
  publishReference();
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
  const WindowKeyframe& newest = mapper_.newestKeyframe();
  init_outcome_ = {true, mapper_.activePointCount(), newest.id(), newest.T_c_w, newest.aff};
  publishReference();
  publishSnapshot();
  events_.initialized(
      InitializedEvent{job.info.frame_index, job.info.timestamp, init_outcome_.points});
  events_.keyframe(KeyframeEvent{newest.id(), job.info.frame_index, job.info.timestamp,
                                 newest.T_c_w.inverse().toPose(), init_outcome_.points});
  spdlog::info("frame {}: initialised with {} points", job.info.frame_index, init_outcome_.points);
}

void MappingStage::reset() {
  publishMap(mapper_.reset());
  if (loop_closer_) loop_closer_->startNewMap();
  references_.clear();
  keyframe_in_flight_.store(false, std::memory_order_release);
  publishSnapshot();
}

void MappingStage::publishMap(MapUpdate&& update) {
  store_.addPoints(update.points);
  for (const KeyframeRecord& r : update.keyframes) store_.setKeyframe(r);
  if (loop_closer_)
    for (MarginalizedKeyframe& kf : update.left) loop_closer_->keyframeLeftWindow(std::move(kf));
}

void MappingStage::applyLoopCorrections() {
  if (!loop_closer_) return;
  for (const loop::LoopCorrection& c : loop_closer_->takeCorrections()) {
    LoopClosureEvent e;
    e.current_keyframe_id = c.current_keyframe_id;
    e.matched_keyframe_id = c.candidate_keyframe_id;
    e.inliers = c.inliers;
    e.scale = c.scale;
    e.time_ms = c.time_ms;
    e.drift_chi2 = c.drift_chi2;
    e.corrected_keyframes = store_.applyCorrection(c.S_world_camera);
    events_.loopClosed(e);
  }
}

void MappingStage::publishReference() {
  mapper_.trackingPoints(depth_points_);
  std::unique_ptr<CoarseTracker> tracker = references_.acquire();
  const TrackingReference r = mapper_.newestReference();
  tracker->setReference(*r.pyramid, camera_, depth_points_, r.exposure, r.aff);
  references_.publish({std::move(tracker), r.keyframe_id, r.T_c_w, r.frame_index});
}

void MappingStage::publishSnapshot() {
  auto s = std::make_shared<MappingSnapshot>();
  s->has_window = mapper_.initialized();
  if (s->has_window) {
    s->active_points = mapper_.activeMapPoints();
    s->newest_T_c_w = mapper_.newestKeyframe().T_c_w;
  }
  s->active_point_count = static_cast<int>(s->active_points.size());
  s->radial_estimate = mapper_.radialEstimate();
  s->radial_applied = mapper_.radialK();
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
    loop_closer_->waitIdle();
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
