#include "pipeline/tracking_stage.h"

#include <spdlog/spdlog.h>

namespace ldsm {

TrackingStageSettings TrackingStageSettings::fromConfig(const Config& config, int levels,
                                                        bool photometry_known) {
  TrackingStageSettings s;
  s.initializer = CoarseInitializerSettings::fromConfig(config, levels, photometry_known);
  s.initializer_hypotheses = config.initializer.hypotheses;
  s.tracker = FrameTrackerSettings::fromConfig(config, photometry_known);
  s.reuse = config.reuse;
  return s;
}

TrackingStage::TrackingStage(const TrackingStageSettings& settings, const PyramidCamera& camera,
                             FramePreprocessor& preprocessor, PyramidPool& pyramids,
                             MapStore& store, MappingStage& mapping, EventSink& events)
    : preprocessor_(preprocessor),
      pyramids_(pyramids),
      store_(store),
      mapping_(mapping),
      events_(events),
      initializer_(camera, settings.initializer, settings.initializer_hypotheses),
      tracker_(settings.tracker, camera),
      timer_({"preprocess", "initialize", "track", "total"}, 20000),
      relocalization_timeout_s_(settings.reuse.relocalization_timeout_s) {
  if (settings.reuse.enabled && relocalization_timeout_s_ > 0.0)
    relocalizer_ = std::make_unique<Relocalizer>(settings.reuse, camera);
}

FrameEvent TrackingStage::process(ImageView<const std::uint8_t> image, std::int64_t index,
                                  double timestamp, double exposure) {
  FrameEvent frame;
  frame.frame_index = index;
  frame.timestamp = timestamp;
  {
    StageTimer::Scope total(timer_, kTotal);
    std::unique_ptr<ImagePyramid> pyr = pyramids_.acquire();
    {
      StageTimer::Scope t(timer_, kPreprocess);
      preprocessor_.process(image, *pyr);
    }
    if (relocalizing_ && timestamp - lost_since_ > relocalization_timeout_s_) startNewMap();
    if (status_ == TrackingStatus::Tracking) {
      trackStep(std::move(pyr), frame, exposure);
    } else if (relocalizing_) {
      relocalizeStep(std::move(pyr), frame, exposure);
    } else {
      initializeStep(std::move(pyr), frame, exposure);
    }
  }
  frame.status = status_;
  events_.frame(frame);
  return frame;
}

void TrackingStage::initializeStep(std::unique_ptr<ImagePyramid> pyr, FrameEvent& frame,
                                   double exposure) {
  StageTimer::Scope t(timer_, kInitialize);
  const std::int64_t index = frame.frame_index;
  const bool done = initializer_.addFrame(*pyr, exposure);
  const InitFrameStats& is = initializer_.lastFrameStats();
  spdlog::debug("frame {}: initialiser {} (flow {:.1f} px, rms {:.1f}, good {:.0f} %)", index,
                toString(initializer_.status()), is.flow_translation, is.rms_residual,
                100.0 * is.good_fraction);
  if (initializer_.framesTracked() == 0 && !done) {
    // This frame became the initializer's reference: keep its pyramid for the first keyframe.
    pyramids_.release(std::move(init_reference_));
    init_reference_ = std::move(pyr);
    init_reference_info_ = {index, frame.timestamp, exposure, world_anchor_, AffineLight{}, {}};
    return;
  }
  if (!done) {
    if (initializer_.failed())
      spdlog::info("frame {}: initialisation restarts ({})", index,
                   toString(initializer_.failure()));
    pyramids_.release(std::move(pyr));
    return;
  }
  // The map is made by the mapping stage; tracking needs it before the next frame.
  const InitializationResult& r = initializer_.result();
  MappingJob job;
  job.kind = MappingJob::Kind::kInitialize;
  job.pyramid = std::move(pyr);
  job.info = {index, frame.timestamp, exposure, r.T_frame_ref * world_anchor_, r.affine_frame, {}};
  job.initialization = r;
  job.reference_pyramid = std::move(init_reference_);
  job.reference_info = init_reference_info_;
  mapping_.submit(std::move(job));
  mapping_.waitIdle();
  const InitializationOutcome& outcome = mapping_.lastInitialization();
  if (!outcome.ok) {
    initializer_.reset();
    return;
  }
  initializer_.releaseMemory();
  status_ = TrackingStatus::Tracking;
  ++initializations_;
  store_.addFrame({init_reference_info_.frame_index, init_reference_info_.timestamp,
                   outcome.keyframe_id - 1, SE3d()});
  store_.addFrame({index, frame.timestamp, outcome.keyframe_id, SE3d()});
  adoptNewestReference();
  tracker_.resetMotion(outcome.T_c_w, outcome.aff);
  last_tracked_index_ = index;
  frame.has_pose = true;
  frame.is_keyframe = true;
  frame.pose = outcome.T_c_w.inverse().toPose();
}

void TrackingStage::trackStep(std::unique_ptr<ImagePyramid> pyr, FrameEvent& frame,
                              double exposure) {
  adoptNewestReference();
  const FrameTracker::MotionState motion = tracker_.motionState();
  FrameTrackingOutcome outcome;
  {
    StageTimer::Scope t(timer_, kTrack);
    outcome = tracker_.track(*pyr, exposure);
  }
  if (mapping_.keyframeInFlight()) {
    // Tracked against the reference before the keyframe the mapping stage is integrating. Never
    // wait for it: a failed frame is tracked again against a reference published meanwhile, if
    // any, or else goes without a pose (the next frame has the new reference); a frame that
    // wants a keyframe does not make another one (the next frame decides against the new one).
    if (!outcome.success && adoptNewestReference()) {
      tracker_.restoreMotion(motion);
      StageTimer::Scope t(timer_, kTrack);
      outcome = tracker_.track(*pyr, exposure);
    }
    if (!outcome.success && mapping_.keyframeInFlight()) {
      spdlog::debug("frame {}: not tracked while a keyframe is mapped ({})", frame.frame_index,
                    outcome.failure);
      tracker_.restoreMotion(motion);
      pyramids_.release(std::move(pyr));
      return;
    }
    if (outcome.success && mapping_.keyframeInFlight()) outcome.wants_keyframe = false;
  }
  if (!outcome.success) {
    pyramids_.release(std::move(pyr));
    loseTracking(frame, "frame " + std::to_string(frame.frame_index) + ": " + outcome.failure);
    return;
  }
  acceptTrackedFrame(std::move(pyr), frame, exposure, outcome);
}

void TrackingStage::acceptTrackedFrame(std::unique_ptr<ImagePyramid> pyr, FrameEvent& frame,
                                       double exposure, const FrameTrackingOutcome& outcome) {
  const SE3d T_ref_w = tracker_.referencePose();
  store_.addFrame({frame.frame_index, frame.timestamp, tracker_.referenceKeyframeId(),
                   T_ref_w * outcome.T_c_w.inverse()});
  last_tracked_index_ = frame.frame_index;
  frame.has_pose = true;
  frame.pose = outcome.T_c_w.inverse().toPose();
  frame.residual_rmse = outcome.rmse;
  frame.is_keyframe = outcome.wants_keyframe;
  MappingJob job;
  job.kind = outcome.wants_keyframe ? MappingJob::Kind::kKeyframe : MappingJob::Kind::kTrace;
  job.pyramid = std::move(pyr);
  job.info = {frame.frame_index, frame.timestamp, exposure, outcome.T_c_w, outcome.aff, {}};
  if (outcome.wants_keyframe) {
    mapping_.setKeyframeInFlight();
    // Room for the frames until the next keyframe (this thread is the frame log's writer).
    store_.reserveFrames(kFrameHeadroom);
  }
  mapping_.submit(std::move(job));
}

bool TrackingStage::adoptNewestReference() {
  PreparedReference ref;
  if (!mapping_.references().takeNewest(ref)) return false;
  tracker_.adoptReference(ref.tracker, ref.keyframe_id, ref.T_c_w);
  mapping_.references().recycle(std::move(ref.tracker));
  // The keyframe was the last tracked frame: continue from its optimised pose.
  if (ref.frame_index == last_tracked_index_) tracker_.refineLastPose(ref.T_c_w);
  return true;
}

void TrackingStage::loseTracking(const FrameEvent& frame, const std::string& reason) {
  spdlog::warn("tracking lost: {}", reason);
  ++losses_;
  events_.trackingLost(TrackingLostEvent{frame.frame_index, frame.timestamp, reason});
  mapping_.waitIdle();
  status_ = TrackingStatus::Lost;
  lost_since_ = frame.timestamp;
  last_good_ = tracker_.motionState();
  // The window and the tracking reference stay while the frame is looked for (relocalizeStep):
  // after a short loss tracking resumes in them.
  relocalizing_ = relocalizer_ != nullptr;
  window_kept_ = true;
  if (!relocalizing_) startNewMap();
}

void TrackingStage::resetWindow() {
  if (!window_kept_) return;
  mapping_.waitIdle();
  // A new map would start where the camera was last seen.
  world_anchor_ = mapping_.snapshot()->newest_T_c_w;
  MappingJob reset;
  reset.kind = MappingJob::Kind::kReset;
  mapping_.submit(std::move(reset));
  mapping_.waitIdle();
  window_kept_ = false;
}

void TrackingStage::startNewMap() {
  resetWindow();
  initializer_.reset();
  relocalizing_ = false;
  MappingJob job;
  job.kind = MappingJob::Kind::kNewMap;
  mapping_.submit(std::move(job));
  mapping_.waitIdle();
}

void TrackingStage::relocalizeStep(std::unique_ptr<ImagePyramid> pyr, FrameEvent& frame,
                                   double exposure) {
  StageTimer::Scope t(timer_, kTrack);
  relocalization_attempts_.fetch_add(1, std::memory_order_relaxed);
  const std::shared_ptr<const MappingSnapshot> snap = mapping_.snapshot();
  const RelocalizationResult r = relocalizer_->relocalize(
      *pyr, exposure, store_, snap->newest_T_c_w, snap->window_ids, snap->median_depth);
  if (window_kept_) {
    // The window is still there: track the frame against its reference, from where the map says
    // the camera is (or, not found, from where it was last seen).
    FrameTracker::MotionState start = last_good_;
    start.has_velocity = false;
    if (r.success) {
      start.T_last_w = r.T_c_w;
      start.last_aff = r.aff;
    }
    tracker_.restoreMotion(start);
    const FrameTrackingOutcome outcome = tracker_.track(*pyr, exposure);
    if (outcome.success) {
      resumeTracking(frame, r.success ? r.keyframe_id : -1, "the window");
      acceptTrackedFrame(std::move(pyr), frame, exposure, outcome);
      return;
    }
  }
  if (!r.success) {
    spdlog::debug("frame {}: not relocalised: {}", frame.frame_index, r.failure);
    pyramids_.release(std::move(pyr));
    return;
  }
  // Found in the map but away from the window: a new window from the map keyframe.
  resetWindow();
  MappingJob job;
  job.kind = MappingJob::Kind::kRelocalize;
  job.pyramid = std::move(pyr);
  job.info = {frame.frame_index, frame.timestamp, exposure, r.T_c_w, r.aff, {}};
  job.anchor_keyframe = r.keyframe_id;
  mapping_.submit(std::move(job));
  mapping_.waitIdle();
  const InitializationOutcome& outcome = mapping_.lastInitialization();
  if (!outcome.ok) return;
  store_.addFrame({frame.frame_index, frame.timestamp, outcome.keyframe_id, SE3d()});
  adoptNewestReference();
  tracker_.resetMotion(outcome.T_c_w, outcome.aff);
  last_tracked_index_ = frame.frame_index;
  frame.has_pose = true;
  frame.is_keyframe = true;
  frame.pose = outcome.T_c_w.inverse().toPose();
  resumeTracking(frame, r.keyframe_id, "map keyframe " + std::to_string(r.keyframe_id));
}

void TrackingStage::resumeTracking(const FrameEvent& frame, int map_keyframe,
                                   const std::string& where) {
  relocalizing_ = false;
  status_ = TrackingStatus::Tracking;
  relocalizations_.fetch_add(1, std::memory_order_relaxed);
  spdlog::info("frame {}: relocalised in {} after {:.2f} s", frame.frame_index, where,
               frame.timestamp - lost_since_);
  events_.relocalized(RelocalizedEvent{frame.frame_index, frame.timestamp,
                                       tracker_.referenceKeyframeId(), map_keyframe,
                                       frame.timestamp - lost_since_});
}

}  // namespace ldsm
