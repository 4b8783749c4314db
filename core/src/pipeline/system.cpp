#include "ldsm/system.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <cmath>

#include "concurrency/latest_value.h"
#include "ldsm/error.h"
#include "mapfile/map_codec.h"
#include "pipeline/frame_worker.h"
#include "pipeline/slam_pipeline.h"
#include "pipeline/stage_settings.h"
#include "pipeline/stage_timer.h"

namespace ldsm {

const char* toString(TrackingStatus status) {
  switch (status) {
    case TrackingStatus::Initializing:
      return "initializing";
    case TrackingStatus::Tracking:
      return "tracking";
    case TrackingStatus::Lost:
      return "lost";
  }
  return "unknown";
}

struct System::Impl {
  enum LatencyStage { kQueueWait, kSubmitToProcessed, kSubmitToTracked };

  Impl(const Config& c, const GeometricCalibration& g, const PhotometricCalibration& p)
      : config(c),
        pipeline(c, g, p),
        input_width(g.input.width),
        input_height(g.input.height),
        latency({"queue_wait", "submit_to_processed", "submit_to_tracked"}, 20000) {}

  /// Checks a frame's metadata and content; returns an empty string when it can be used.
  std::string rejectReason(const FrameView& f) {
    if (!std::isfinite(f.timestamp)) return "timestamp is not a finite number";
    if (frames.load(std::memory_order_relaxed) > 0 && f.timestamp <= last_timestamp)
      return "timestamp " + std::to_string(f.timestamp) + " s is not after the previous one (" +
             std::to_string(last_timestamp) + " s)";
    const bool known = std::isfinite(f.exposure_ms);
    if (!std::isnan(f.exposure_ms) && (!known || f.exposure_ms <= 0.0))
      return "exposure time " + std::to_string(f.exposure_ms) + " ms is not a positive number";
    if (frames.load(std::memory_order_relaxed) > 0 && exposures_known && !known)
      return "exposure time missing (NaN) although earlier frames had one";
    // Black, saturated or flat images carry no information.
    double sum = 0.0, sum_sq = 0.0;
    std::int64_t n = 0;
    for (int y = 0; y < f.image.height; y += 4)
      for (int x = 0; x < f.image.width; x += 4) {
        const double v = f.image(x, y);
        sum += v;
        sum_sq += v * v;
        ++n;
      }
    const double mean = sum / static_cast<double>(std::max<std::int64_t>(n, 1));
    const double var = sum_sq / static_cast<double>(std::max<std::int64_t>(n, 1)) - mean * mean;
    if (var < 1.0)
      return mean < 8.0 ? "image is black" : mean > 247.0 ? "image is saturated" : "image is flat";
    return {};
  }

  static double msSince(std::int64_t start_ns) {
    return static_cast<double>(steadyNowNs() - start_ns) * 1e-6;
  }

  /// Runs on the tracking thread (threaded mode) or in submit() (deterministic mode).
  void process(const FrameView& f, std::int64_t submitted_ns) {
    latency.record(kQueueWait, msSince(submitted_ns));
    const std::string reason = rejectReason(f);
    const std::int64_t index = frames.load(std::memory_order_relaxed);
    frames.store(index + 1, std::memory_order_release);
    if (!reason.empty()) {
      rejected.fetch_add(1, std::memory_order_relaxed);
      spdlog::warn("frame {} rejected: {}", index, reason);
      return;
    }
    if (index == 0 || !exposure_decided) {
      exposures_known = std::isfinite(f.exposure_ms);
      exposure_decided = true;
    }
    last_timestamp = f.timestamp;
    const bool use_exposure = exposures_known && config.photometric.use_exposure;
    const FrameEvent frame = pipeline.tracking().process(f.image, index, f.timestamp,
                                                         use_exposure ? f.exposure_ms : 1.0);
    if (frame.has_pose) {
      tracked.fetch_add(1, std::memory_order_relaxed);
      latest_pose.publish(StampedPose{f.timestamp, frame.pose});
    }
    status.store(pipeline.status(), std::memory_order_release);
    // Always 0 in deterministic mode (the mapping stage runs inline).
    const auto backlog = static_cast<int>(pipeline.mapping().backlog());
    backlog_sum.fetch_add(backlog, std::memory_order_relaxed);
    backlog_samples.fetch_add(1, std::memory_order_relaxed);
    if (backlog > max_backlog.load(std::memory_order_relaxed))
      max_backlog.store(backlog, std::memory_order_relaxed);
    const double done_ms = msSince(submitted_ns);
    latency.record(kSubmitToProcessed, done_ms);
    spdlog::trace("frame {}: submit -> processed {:.1f} ms ({})", index, done_ms,
                  frame.has_pose ? "pose" : "no pose");
    if (frame.has_pose) latency.record(kSubmitToTracked, done_ms);
  }

  Config config;
  SlamPipeline pipeline;
  // Written by the tracking thread only; read by queries from any thread.
  std::atomic<std::int64_t> frames{0};
  std::atomic<std::int64_t> tracked{0};
  std::atomic<std::int64_t> rejected{0};
  std::atomic<std::int64_t> backlog_sum{0};
  std::atomic<std::int64_t> backlog_samples{0};
  std::atomic<int> max_backlog{0};
  // Tracking thread only.
  double last_timestamp = 0.0;
  bool exposures_known = false;
  bool exposure_decided = false;
  int input_width;
  int input_height;
  std::atomic<TrackingStatus> status{TrackingStatus::Initializing};
  mutable concurrency::LatestValue<StampedPose> latest_pose;
  mutable concurrency::LatestValue<TrackedImage> tracked_image;
  StageTimer latency;
  std::unique_ptr<FrameWorker> input;  ///< never null; inline in deterministic mode
};

System::System(const Config& config, const GeometricCalibration& geometric,
               const PhotometricCalibration& photometric) {
  if (config.map.localize_only)
    throw ConfigError("map.localize_only needs a loaded map (ldsm run --load-map FILE)");
  start(config, geometric, photometric);
}

System::System(const Config& config, const GeometricCalibration& geometric,
               const PhotometricCalibration& photometric, const std::vector<std::uint8_t>& map,
               const std::string& where) {
  if (!config.reuse.enabled)
    throw ConfigError("a loaded map needs map reuse (reuse.enabled: true) to be used");
  start(config, geometric, photometric);
  impl_->pipeline.loadMap(decodeMap(map.data(), map.size(), where), where);
}

void System::start(const Config& config, const GeometricCalibration& geometric,
                   const PhotometricCalibration& photometric) {
  validateConfig(config);
  impl_ = std::make_unique<Impl>(config, geometric, photometric);
  // The input stage runs in the mode every stage runs in (stageMode): a tracking thread of its
  // own, or inline on the caller's thread; the mapping stage's thread, if any, is pinned.
  const SystemConfig& sc = config.system;
  const concurrency::TaskMode mode = stageMode(config);
  if (mode == concurrency::TaskMode::kInline && (sc.tracking_cpu >= 0 || sc.mapping_cpu >= 0))
    spdlog::warn(
        "system.tracking_cpu / system.mapping_cpu are ignored in deterministic mode (every "
        "stage runs on the caller's thread)");
  if (const auto mapping = impl_->pipeline.mapping().threadHandle())
    pinThreadToCpu(*mapping, sc.mapping_cpu, "mapping");
  FrameWorkerOptions options;
  options.pool_size = sc.frame_pool_size;
  options.width = impl_->input_width;
  options.height = impl_->input_height;
  options.live = sc.live;
  options.cpu = sc.tracking_cpu;
  options.mode = mode;
  impl_->input = std::make_unique<FrameWorker>(
      [impl = impl_.get()](const FrameView& f, std::int64_t submitted_ns) {
        impl->process(f, submitted_ns);
      },
      options);
}

std::vector<std::uint8_t> System::saveMap() {
  finish();
  return encodeMap(impl_->pipeline.exportMap());
}

System::~System() {
  if (impl_ && impl_->input) impl_->input->stop();
}

void System::setListener(SystemListener* listener) {
  impl_->pipeline.setListener(listener);
}

void System::submit(const FrameView& frame) {
  if (frame.image.empty()) throw InputError("submitted frame has no image data");
  const int w = impl_->input_width, h = impl_->input_height;
  if (frame.image.width != w || frame.image.height != h)
    throw InputError("frame at t = " + std::to_string(frame.timestamp) + " s is " +
                     std::to_string(frame.image.width) + "x" + std::to_string(frame.image.height) +
                     " but the camera is " + std::to_string(w) + "x" + std::to_string(h));
  impl_->input->push(frame);
}

void System::finish() {
  impl_->input->drain();
  impl_->pipeline.finish();
}

TrackingStatus System::status() const {
  return impl_->status.load(std::memory_order_acquire);
}

std::optional<StampedPose> System::latestPose() const {
  StampedPose pose;
  if (!impl_->latest_pose.readLatest(pose)) return std::nullopt;
  return pose;
}

void System::publishTrackedImages() {
  impl_->pipeline.tracking().setImageOutput(&impl_->tracked_image);
}

std::optional<TrackedImage> System::latestTrackedImage() const {
  TrackedImage image;
  if (!impl_->tracked_image.readLatest(image)) return std::nullopt;
  return image;
}

Trajectory System::trajectory() const {
  return impl_->pipeline.trajectory();
}

Trajectory System::takeRetiredFrames() {
  return impl_->pipeline.takeRetiredFrames();
}

Trajectory System::keyframeTrajectory() const {
  return impl_->pipeline.keyframeTrajectory();
}

std::vector<MapPoint> System::mapPoints() const {
  return impl_->pipeline.mapPoints();
}

SystemStats System::stats() const {
  SystemStats s;
  s.frames = impl_->frames.load(std::memory_order_acquire);
  s.tracked_frames = impl_->tracked.load(std::memory_order_relaxed);
  s.rejected_frames = impl_->rejected.load(std::memory_order_relaxed);
  impl_->pipeline.fillStats(s);
  const std::int64_t samples = impl_->backlog_samples.load(std::memory_order_relaxed);
  s.max_mapping_backlog = impl_->max_backlog.load(std::memory_order_relaxed);
  s.mean_mapping_backlog =
      samples > 0 ? static_cast<double>(impl_->backlog_sum.load(std::memory_order_relaxed)) /
                        static_cast<double>(samples)
                  : 0.0;
  // Read after `frames`: submitted >= frames + dropped holds in every snapshot.
  const FrameWorkerCounts c = impl_->input->counts();
  s.submitted_frames = c.submitted;
  s.dropped_frames = c.dropped;
  s.queue_capacity = c.queue_capacity;
  s.max_queue_depth = c.max_queue_depth;
  s.mean_queue_depth = c.mean_queue_depth;
  // A frame waits in a queue only in threaded mode.
  for (StageTiming& t : impl_->latency.summary())
    if (impl_->input->queued() || t.stage != "queue_wait") s.latency.push_back(std::move(t));
  return s;
}

PinholeIntrinsics System::rectifiedCamera() const {
  const LevelCamera& c = impl_->pipeline.camera()[0];
  return {c.fx, c.fy, c.cx, c.cy, c.width, c.height};
}

}  // namespace ldsm
