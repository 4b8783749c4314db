// Odometry's threaded mode: the mapping thread and its hand-overs with the tracking thread.
//   tracking thread --(MappingJob: pyramid, pose, keyframe flag; SPSC ring)--> mapping thread
//   mapping thread --(coarse tracker prepared for the new keyframe; swapped under a mutex
//                     once per keyframe)--> tracking thread
#include <spdlog/spdlog.h>

#include <chrono>

#include "pipeline/odometry.h"
#include "pipeline/ring_wait.h"

namespace ldsm {

namespace {
constexpr std::size_t kMappingQueue = 4;  // frames the tracking thread may run ahead
}  // namespace

void Odometry::startMappingThread(std::function<void(const KeyframeEvent&)> on_keyframe) {
  if (threaded()) return;
  on_keyframe_ = std::move(on_keyframe);
  mapping_ring_ = std::make_unique<pipeline::SpscRing<MappingJob>>(kMappingQueue);
  spare_reference_ = tracker_.makeCoarseTracker();
  mapping_depth_points_.reserve(64 * 1024);
  mapping_stop_.store(false);
  mapping_thread_ = std::thread([this] { mappingLoop(); });
}

void Odometry::stopMappingThread() {
  if (!mapping_thread_.joinable()) return;
  mapping_stop_.store(true, std::memory_order_release);
  mapping_thread_.join();
}

std::size_t Odometry::mappingBacklog() const {
  return threaded() ? mapping_ring_->size() : 0;
}

void Odometry::waitForMapping() {
  if (!threaded()) return;
  for (pipeline::Backoff backoff;
       jobs_done_.load(std::memory_order_acquire) < jobs_pushed_.load(std::memory_order_relaxed);
       backoff.pause()) {
  }
}

void Odometry::handOverToMapping(std::unique_ptr<ImagePyramid> pyramid, const MapperFrame& info,
                                 bool keyframe) {
  MappingJob job{std::move(pyramid), info, keyframe};
  jobs_pushed_.fetch_add(1, std::memory_order_relaxed);
  if (!pipeline::pushWaiting(*mapping_ring_, std::move(job), mapping_stop_)) {
    mapper_.releasePyramid(std::move(job.pyramid));
    jobs_done_.fetch_add(1, std::memory_order_release);
  }
}

void Odometry::mappingLoop() {
  MappingJob job;
  while (pipeline::popWaiting(*mapping_ring_, job, mapping_stop_)) {
    try {
      mapJob(job);
    } catch (const std::exception& e) {
      spdlog::error("mapping failed on frame {}: {}", job.info.frame_index, e.what());
      keyframe_in_flight_.store(false);
    }
    mapper_.releasePyramid(std::move(job.pyramid));
    jobs_done_.fetch_add(1, std::memory_order_release);
  }
}

void Odometry::mapJob(MappingJob& job) {
  if (!job.keyframe) {
    // Behind: skip the tracing of ordinary frames until the queue is short again.
    if (mapping_ring_->size() > 1) return;
    std::lock_guard<std::mutex> lock(mapper_mutex_);
    StageTimer::Scope t(mapping_timer_, kTrace);
    mapper_.traceFrame(*job.pyramid, job.info);
    return;
  }
  KeyframeEvent event;
  {
    std::lock_guard<std::mutex> lock(mapper_mutex_);
    StageTimer::Scope t(mapping_timer_, kMapping);
    mapper_.traceFrame(*job.pyramid, job.info);
    const KeyframeInsertion ins = mapper_.addKeyframe(std::move(job.pyramid), job.info);
    keyframes_.fetch_add(1, std::memory_order_relaxed);
    applyLoopCorrections();
    publishReference();
    const WindowKeyframe& newest = mapper_.newestKeyframe();
    event = KeyframeEvent{newest.id(), job.info.frame_index, job.info.timestamp,
                          newest.T_c_w.inverse().toPose(), ins.active_points};
    spdlog::debug(
        "keyframe {} (frame {}): {} active, {} activated, {} marginalised, {} left the "
        "view (mapping thread)",
        newest.id(), job.info.frame_index, ins.active_points, ins.activated_points,
        ins.marginalized_frames, ins.retired_points);
  }
  keyframe_in_flight_.store(false);
  if (on_keyframe_) on_keyframe_(event);
}

void Odometry::publishReference() {
  mapper_.trackingPoints(mapping_depth_points_);
  std::unique_ptr<CoarseTracker> prepared;
  {
    std::lock_guard<std::mutex> lock(reference_mutex_);
    prepared = spare_reference_ ? std::move(spare_reference_) : std::move(pending_reference_);
  }
  if (!prepared) prepared = tracker_.makeCoarseTracker();
  const WindowKeyframe& kf = mapper_.newestKeyframe();
  prepared->setReference(kf.pyramid(), camera_, mapping_depth_points_, kf.exposure(), kf.aff);
  std::lock_guard<std::mutex> lock(reference_mutex_);
  if (pending_reference_) spare_reference_ = std::move(pending_reference_);
  pending_reference_ = std::move(prepared);
  pending_id_ = kf.id();
  pending_T_c_w_ = kf.T_c_w;
  pending_frame_index_ = kf.frameIndex();
  has_pending_reference_.store(true, std::memory_order_release);
}

void Odometry::adoptPreparedReference() {
  if (!has_pending_reference_.load(std::memory_order_acquire)) return;
  std::lock_guard<std::mutex> lock(reference_mutex_);
  if (!pending_reference_) return;
  tracker_.adoptReference(pending_reference_, pending_id_, pending_T_c_w_);
  spare_reference_ = std::move(pending_reference_);
  has_pending_reference_.store(false, std::memory_order_relaxed);
  // The keyframe was the last tracked frame: continue from its optimised pose.
  if (pending_frame_index_ == last_tracked_index_) tracker_.refineLastPose(pending_T_c_w_);
}

std::vector<StageTiming> Odometry::timings() const {
  std::vector<StageTiming> t = timer_.summary();
  if (!threaded()) return t;
  std::vector<StageTiming> m;
  {
    std::lock_guard<std::mutex> lock(mapper_mutex_);  // the mapping thread records under it
    m = mapping_timer_.summary();
  }
  for (std::size_t i = 0; i < t.size() && i < m.size(); ++i)
    if (t[i].count == 0 && m[i].count > 0) t[i] = m[i];
  return t;
}

}  // namespace ldsm
