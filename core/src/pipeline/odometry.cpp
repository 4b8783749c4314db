#include "pipeline/odometry.h"

#include <spdlog/spdlog.h>

#include <algorithm>

#include "pipeline/backoff.h"

namespace ldsm {
namespace {

int usableLevels(const PinholeIntrinsics& k, int wanted) {
  int levels = 1;
  while (levels < wanted && (k.width >> levels) >= 20 && (k.height >> levels) >= 15) ++levels;
  return levels;
}

}  // namespace

Odometry::Odometry(const Config& config, const GeometricCalibration& geometric,
                   const PhotometricCalibration& photometric)
    : config_(config),
      preprocessor_(geometric, photometric, config.photometric),
      camera_(preprocessor_.output(),
              usableLevels(preprocessor_.output(), config.tracking.pyramid_levels)),
      mapper_(config, camera_, store_,
              preprocessor_.photometricallyCalibrated() && config.photometric.use_exposure),
      initializer_(
          camera_,
          CoarseInitializerSettings::fromConfig(
              config, camera_.levels(),
              preprocessor_.photometricallyCalibrated() && config.photometric.use_exposure),
          config.initializer.hypotheses),
      tracker_(config, camera_,
               preprocessor_.photometricallyCalibrated() && config.photometric.use_exposure),
      timer_({"preprocess", "initialize", "track", "trace", "mapping", "total"}, 20000),
      mapping_timer_({"preprocess", "initialize", "track", "trace", "mapping", "total"}, 20000) {
  if (config.loop.enabled) {
    const LevelCamera& c = camera_[0];
    loop_closer_ = std::make_unique<loop::LoopCloser>(
        config.loop, PinholeIntrinsics{c.fx, c.fy, c.cx, c.cy, c.width, c.height},
        /*inline_mode=*/config.system.deterministic);
    mapper_.setKeyframeLeavingHandler(
        [this](MarginalizedKeyframe&& kf) { loop_closer_->keyframeLeftWindow(std::move(kf)); });
  }
}

Odometry::~Odometry() {
  stopMappingThread();
  loop_closer_.reset();
}

void Odometry::applyLoopCorrections() {
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
    {
      std::lock_guard<std::mutex> lock(loops_mutex_);
      loops_.push_back(e);
    }
    if (on_loop_) on_loop_(e);
  }
}

void Odometry::finishLoops() {
  if (!loop_closer_) return;
  loop_closer_->waitIdle();
  std::lock_guard<std::mutex> lock(mapper_mutex_);
  applyLoopCorrections();
}

std::vector<LoopClosureEvent> Odometry::loops() const {
  std::lock_guard<std::mutex> lock(loops_mutex_);
  return loops_;
}

OdometryStep Odometry::process(ImageView<const std::uint8_t> image, std::int64_t index,
                               double timestamp, double exposure) {
  StageTimer::Scope total(timer_, kTotal);
  std::unique_ptr<ImagePyramid> pyr = mapper_.acquirePyramid();
  {
    StageTimer::Scope t(timer_, kPreprocess);
    preprocessor_.process(image, *pyr);
  }
  OdometryStep step = status_ == TrackingStatus::Tracking
                          ? trackStep(std::move(pyr), index, timestamp, exposure)
                          : initializeStep(std::move(pyr), index, timestamp, exposure);
  step.frame.frame_index = index;
  step.frame.timestamp = timestamp;
  step.frame.status = status_;
  return step;
}

OdometryStep Odometry::initializeStep(std::unique_ptr<ImagePyramid> pyr, std::int64_t index,
                                      double timestamp, double exposure) {
  OdometryStep step;
  StageTimer::Scope t(timer_, kInitialize);
  const bool done = initializer_.addFrame(*pyr, exposure);
  const InitFrameStats& is = initializer_.lastFrameStats();
  spdlog::debug("frame {}: initialiser {} (flow {:.1f} px, rms {:.1f}, good {:.0f} %)", index,
                toString(initializer_.status()), is.flow_translation, is.rms_residual,
                100.0 * is.good_fraction);
  if (initializer_.framesTracked() == 0 && !done) {
    // This frame became the initializer's reference: keep its pyramid for the first keyframe.
    mapper_.releasePyramid(std::move(init_reference_));
    init_reference_ = std::move(pyr);
    init_reference_info_ = {index, timestamp, exposure, world_anchor_, AffineLight{}};
    return step;
  }
  if (!done) {
    if (initializer_.failed())
      spdlog::info("frame {}: initialisation restarts ({})", index,
                   toString(initializer_.failure()));
    mapper_.releasePyramid(std::move(pyr));
    return step;
  }
  const InitializationResult& r = initializer_.result();
  MapperFrame last{index, timestamp, exposure, r.T_frame_ref * world_anchor_, r.affine_frame};
  // The mapping thread (threaded mode) is idle until the map exists.
  std::lock_guard<std::mutex> lock(mapper_mutex_);
  KeyframeInsertion ins;
  const bool ok = mapper_.initialize(r, init_reference_info_, std::move(init_reference_), last,
                                     std::move(pyr), &ins);
  if (ok) {
    initializer_.releaseMemory();
  } else {
    initializer_.reset();
  }
  if (!ok) return step;
  status_ = TrackingStatus::Tracking;
  ++initializations_;
  keyframes_ += 2;
  const WindowKeyframe& newest = mapper_.newestKeyframe();
  store_.addFrame(
      {init_reference_info_.frame_index, init_reference_info_.timestamp, newest.id() - 1, SE3d()});
  store_.addFrame({index, timestamp, newest.id(), SE3d()});
  updateTrackerReference();
  tracker_.resetMotion(newest.T_c_w, newest.aff);
  last_tracked_index_ = index;
  step.initialized = InitializedEvent{index, timestamp, mapper_.activePointCount()};
  step.frame.has_pose = true;
  step.frame.is_keyframe = true;
  step.frame.pose = newest.T_c_w.inverse().toPose();
  step.keyframe =
      KeyframeEvent{newest.id(), index, timestamp, step.frame.pose, mapper_.activePointCount()};
  spdlog::info("frame {}: initialised with {} points", index, mapper_.activePointCount());
  return step;
}

OdometryStep Odometry::trackStep(std::unique_ptr<ImagePyramid> pyr, std::int64_t index,
                                 double timestamp, double exposure) {
  OdometryStep step;
  step.frame.frame_index = index;
  step.frame.timestamp = timestamp;
  FrameTrackingOutcome outcome;
  if (threaded()) adoptPreparedReference();
  const FrameTracker::MotionState motion = tracker_.motionState();
  {
    StageTimer::Scope t(timer_, kTrack);
    outcome = tracker_.track(*pyr, exposure);
  }
  if (threaded() && (!outcome.success || outcome.wants_keyframe) &&
      keyframe_in_flight_.load(std::memory_order_acquire)) {
    // Tracked against the reference before the keyframe the mapping thread is integrating, and
    // not good enough (the camera moves fast): wait for the new reference and track again.
    for (pipeline::Backoff backoff; keyframe_in_flight_.load(std::memory_order_acquire);
         backoff.pause()) {
    }
    adoptPreparedReference();
    tracker_.restoreMotion(motion);
    StageTimer::Scope t(timer_, kTrack);
    outcome = tracker_.track(*pyr, exposure);
  }
  if (!outcome.success) {
    mapper_.releasePyramid(std::move(pyr));
    loseTracking(step, "frame " + std::to_string(index) + ": " + outcome.failure);
    return step;
  }
  const SE3d T_ref_w = tracker_.referencePose();
  store_.addFrame(
      {index, timestamp, tracker_.referenceKeyframeId(), T_ref_w * outcome.T_c_w.inverse()});
  MapperFrame info{index, timestamp, exposure, outcome.T_c_w, outcome.aff};
  last_tracked_index_ = index;
  if (threaded()) {
    const bool keyframe = outcome.wants_keyframe;
    if (keyframe) keyframe_in_flight_.store(true, std::memory_order_release);
    step.frame.has_pose = true;
    step.frame.pose = outcome.T_c_w.inverse().toPose();
    step.frame.residual_rmse = outcome.rmse;
    step.frame.is_keyframe = keyframe;
    handOverToMapping(std::move(pyr), info, keyframe);
    return step;
  }
  {
    StageTimer::Scope t(timer_, kTrace);
    mapper_.traceFrame(*pyr, info);
  }
  step.frame.has_pose = true;
  step.frame.pose = outcome.T_c_w.inverse().toPose();
  step.frame.residual_rmse = outcome.rmse;
  if (!outcome.wants_keyframe) {
    mapper_.releasePyramid(std::move(pyr));
    return step;
  }
  StageTimer::Scope t(timer_, kMapping);
  const KeyframeInsertion ins = mapper_.addKeyframe(std::move(pyr), info);
  keyframes_.fetch_add(1, std::memory_order_relaxed);
  applyLoopCorrections();
  const WindowKeyframe& newest = mapper_.newestKeyframe();
  tracker_.refineLastPose(newest.T_c_w);
  updateTrackerReference();
  step.frame.is_keyframe = true;
  step.keyframe = KeyframeEvent{newest.id(), index, timestamp, newest.T_c_w.inverse().toPose(),
                                ins.active_points};
  spdlog::debug(
      "keyframe {} (frame {}): {} active, {} activated, {} marginalised, rmse {:.2f}, "
      "{} left the view",
      newest.id(), index, ins.active_points, ins.activated_points, ins.marginalized_frames,
      ins.optimization.rmse, ins.retired_points);
  return step;
}

void Odometry::updateTrackerReference() {
  mapper_.trackingPoints(depth_points_);
  tracker_.setReference(mapper_.newestKeyframe(), depth_points_);
}

void Odometry::loseTracking(OdometryStep& step, const std::string& reason) {
  spdlog::warn("tracking lost: {}", reason);
  ++losses_;
  step.lost = TrackingLostEvent{step.frame.frame_index, step.frame.timestamp, reason};
  if (threaded()) {
    waitForMapping();
    std::lock_guard<std::mutex> lock(reference_mutex_);
    if (pending_reference_) spare_reference_ = std::move(pending_reference_);
    has_pending_reference_.store(false);
    keyframe_in_flight_.store(false);
  }
  std::lock_guard<std::mutex> lock(mapper_mutex_);
  // The next map starts where the camera was last seen.
  world_anchor_ = mapper_.newestKeyframe().T_c_w;
  mapper_.reset();
  if (loop_closer_) loop_closer_->startNewMap();
  initializer_.reset();
  status_ = TrackingStatus::Lost;
}

void Odometry::flush() {
  std::lock_guard<std::mutex> lock(mapper_mutex_);
  mapper_.publishPoses();
}

Eigen::Vector2d Odometry::radialCorrection() const {
  std::lock_guard<std::mutex> lock(mapper_mutex_);
  return {mapper_.radialEstimate(), mapper_.radialK()};
}

std::vector<MapPoint> Odometry::mapPoints() const {
  std::lock_guard<std::mutex> lock(mapper_mutex_);
  std::vector<MapPoint> pts = store_.points();
  const std::vector<MapPoint> active = mapper_.activeMapPoints();
  pts.insert(pts.end(), active.begin(), active.end());
  return pts;
}

}  // namespace ldsm
