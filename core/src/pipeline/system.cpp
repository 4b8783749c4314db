#include "ldsm/system.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>

#include "ldsm/error.h"
#include "pipeline/frame_worker.h"
#include "pipeline/latest_value.h"
#include "pipeline/odometry.h"
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
  enum LatencyStage { kQueueWait, kSubmitToTracked };

  Impl(const Config& c, const GeometricCalibration& g, const PhotometricCalibration& p)
      : config(c),
        odometry(c, g, p),
        input_width(g.input.width),
        input_height(g.input.height),
        latency({"queue_wait", "submit_to_tracked"}, 20000) {}

  /// Checks a frame's metadata and content; returns an empty string when it can be used.
  std::string rejectReason(const FrameView& f) {
    if (!std::isfinite(f.timestamp)) return "timestamp is not a finite number";
    if (frames > 0 && f.timestamp <= last_timestamp)
      return "timestamp " + std::to_string(f.timestamp) + " s is not after the previous one (" +
             std::to_string(last_timestamp) + " s)";
    const bool known = std::isfinite(f.exposure_ms);
    if (!std::isnan(f.exposure_ms) && (!known || f.exposure_ms <= 0.0))
      return "exposure time " + std::to_string(f.exposure_ms) + " ms is not a positive number";
    if (frames > 0 && exposures_known && !known)
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
    std::lock_guard<std::mutex> lock(mutex);
    if (worker) latency.record(kQueueWait, msSince(submitted_ns));
    const std::string reason = rejectReason(f);
    const std::int64_t index = frames++;
    if (!reason.empty()) {
      ++rejected;
      spdlog::warn("frame {} rejected: {}", index, reason);
      return;
    }
    if (index == 0 || !exposure_decided) {
      exposures_known = std::isfinite(f.exposure_ms);
      exposure_decided = true;
    }
    last_timestamp = f.timestamp;
    const bool use_exposure = exposures_known && config.photometric.use_exposure;
    const OdometryStep step =
        odometry.process(f.image, index, f.timestamp, use_exposure ? f.exposure_ms : 1.0);
    if (step.frame.has_pose) {
      ++tracked;
      latest_pose.publish(StampedPose{f.timestamp, step.frame.pose});
    }
    status.store(odometry.status(), std::memory_order_release);
    if (worker) {
      const auto backlog = static_cast<int>(odometry.mappingBacklog());
      backlog_sum += backlog;
      ++backlog_samples;
      max_backlog = std::max(max_backlog, backlog);
    }
    latency.record(kSubmitToTracked, msSince(submitted_ns));
    if (listener) {
      if (step.lost) listener->onTrackingLost(*step.lost);
      if (step.initialized) listener->onInitialized(*step.initialized);
      if (step.keyframe) listener->onKeyframe(*step.keyframe);
      listener->onFrame(step.frame);
    }
  }

  Config config;
  Odometry odometry;
  SystemListener* listener = nullptr;
  mutable std::mutex mutex;  ///< processing vs. queries of the results
  std::int64_t frames = 0;
  std::int64_t tracked = 0;
  std::int64_t rejected = 0;
  double last_timestamp = 0.0;
  bool exposures_known = false;
  bool exposure_decided = false;
  int input_width;
  int input_height;
  std::atomic<TrackingStatus> status{TrackingStatus::Initializing};
  mutable pipeline::LatestValue<StampedPose> latest_pose;
  StageTimer latency;
  std::int64_t backlog_sum = 0;
  std::int64_t backlog_samples = 0;
  int max_backlog = 0;
  std::unique_ptr<FrameWorker> worker;
};

System::System(const Config& config, const GeometricCalibration& geometric,
               const PhotometricCalibration& photometric) {
  validateConfig(config);
  impl_ = std::make_unique<Impl>(config, geometric, photometric);
  impl_->odometry.setLoopHandler([impl = impl_.get()](const LoopClosureEvent& e) {
    if (impl->listener) impl->listener->onLoopClosure(e);
  });
  const SystemConfig& sc = config.system;
  if (sc.deterministic) {
    if (sc.tracking_cpu >= 0 || sc.mapping_cpu >= 0)
      spdlog::warn(
          "system.tracking_cpu / system.mapping_cpu are ignored in deterministic mode (every "
          "stage runs on the caller's thread)");
    return;
  }
  // Tracking on the frame worker's thread, mapping on the odometry's mapping thread.
  impl_->odometry.startMappingThread([impl = impl_.get()](const KeyframeEvent& e) {
    if (impl->listener) impl->listener->onKeyframe(e);
  });
  pinThreadToCpu(impl_->odometry.mappingThreadHandle(), sc.mapping_cpu, "mapping");
  FrameWorkerOptions options;
  options.pool_size = sc.frame_pool_size;
  options.width = impl_->input_width;
  options.height = impl_->input_height;
  options.live = sc.live;
  options.cpu = sc.tracking_cpu;
  impl_->worker = std::make_unique<FrameWorker>(
      [impl = impl_.get()](const FrameView& f, std::int64_t submitted_ns) {
        impl->process(f, submitted_ns);
      },
      options);
}

System::~System() {
  if (impl_ && impl_->worker) impl_->worker->stop();
}

void System::setListener(SystemListener* listener) {
  impl_->listener = listener;
}

void System::submit(const FrameView& frame) {
  if (frame.image.empty()) throw InputError("submitted frame has no image data");
  const int w = impl_->input_width, h = impl_->input_height;
  if (frame.image.width != w || frame.image.height != h)
    throw InputError("frame at t = " + std::to_string(frame.timestamp) + " s is " +
                     std::to_string(frame.image.width) + "x" + std::to_string(frame.image.height) +
                     " but the camera is " + std::to_string(w) + "x" + std::to_string(h));
  if (impl_->worker) {
    impl_->worker->push(frame);
  } else {
    impl_->process(frame, steadyNowNs());
  }
}

void System::finish() {
  if (impl_->worker) impl_->worker->drain();
  impl_->odometry.waitForMapping();
  impl_->odometry.finishLoops();
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->odometry.flush();
}

TrackingStatus System::status() const {
  return impl_->status.load(std::memory_order_acquire);
}

std::optional<StampedPose> System::latestPose() const {
  StampedPose pose;
  if (!impl_->latest_pose.readLatest(pose)) return std::nullopt;
  return pose;
}

Trajectory System::trajectory() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->odometry.flush();
  return impl_->odometry.store().frameTrajectory();
}

Trajectory System::keyframeTrajectory() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->odometry.flush();
  return impl_->odometry.store().keyframeTrajectory();
}

std::vector<MapPoint> System::mapPoints() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->odometry.mapPoints();
}

SystemStats System::stats() const {
  SystemStats s;
  StageTimer latency({}, 0);
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    s.frames = impl_->frames;
    s.tracked_frames = impl_->tracked;
    s.keyframes = impl_->odometry.keyframes();
    s.initializations = impl_->odometry.initializations();
    s.tracking_losses = impl_->odometry.losses();
    s.rejected_frames = impl_->rejected;
    s.stages = impl_->odometry.timings();
    s.loops = impl_->odometry.loops();
    const Eigen::Vector2d radial = impl_->odometry.radialCorrection();
    s.radial_estimate = radial.x();
    s.radial_applied = radial.y();
    latency = impl_->latency;  // copied under the lock, summarised outside it
    s.max_mapping_backlog = impl_->max_backlog;
    s.mean_mapping_backlog =
        impl_->backlog_samples > 0
            ? static_cast<double>(impl_->backlog_sum) / static_cast<double>(impl_->backlog_samples)
            : 0.0;
  }
  // Read after `frames`: submitted >= frames + dropped holds in every snapshot.
  if (impl_->worker) {
    const FrameWorkerCounts c = impl_->worker->counts();
    s.submitted_frames = c.submitted;
    s.dropped_frames = c.dropped;
    s.queue_capacity = c.queue_capacity;
    s.max_queue_depth = c.max_queue_depth;
    s.mean_queue_depth = c.mean_queue_depth;
  } else {
    s.submitted_frames = s.frames;
  }
  s.mapping_backlog = static_cast<int>(impl_->odometry.mappingBacklog());
  for (StageTiming& t : latency.summary())
    if (impl_->worker || t.stage != "queue_wait") s.latency.push_back(std::move(t));
  return s;
}

PinholeIntrinsics System::rectifiedCamera() const {
  const LevelCamera& c = impl_->odometry.camera()[0];
  return {c.fx, c.fy, c.cx, c.cy, c.width, c.height};
}

}  // namespace ldsm
