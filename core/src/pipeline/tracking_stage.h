// The tracking stage: what happens to every frame on the tracking thread (the caller's thread in
// deterministic mode). The frame is preprocessed into a pyramid; until a map exists it goes to
// the initializer, and a finished initialisation becomes a job for the mapping stage (in live
// mode the initializer runs on a thread of its own, which takes the newest frame whenever it is
// free, so that the tracking thread never waits for it: see initializeStep()); afterwards
// it is tracked against the newest reference the mapping stage published (ReferenceExchange),
// its pose goes to the map store, and the frame goes on to the mapping stage (to trace, or as a
// keyframe). A failed frame loses tracking: the window goes to the map, and the next frames are
// looked for in the map (reuse/relocalizer.h); found, tracking resumes in the same map frame.
// Only when that fails for reuse.relocalization_timeout_s does a new map start, initialised where
// the camera was last seen.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "concurrency/background_task.h"
#include "concurrency/latest_value.h"
#include "frontend/coarse_initializer_settings.h"
#include "frontend/frame_tracker.h"
#include "frontend/initializer_hypotheses.h"
#include "image/pyramid_pool.h"
#include "ldsm/config.h"
#include "ldsm/events.h"
#include "ldsm/system.h"
#include "map/map_store.h"
#include "pipeline/event_sink.h"
#include "pipeline/frame_preprocessor.h"
#include "pipeline/mapping_stage.h"
#include "pipeline/stage_timer.h"
#include "reuse/relocalizer.h"

namespace ldsm {

/// The tracking stage's settings: its sections of the configuration and what is derived from them.
struct TrackingStageSettings {
  CoarseInitializerSettings initializer;
  int initializer_hypotheses = 7;  ///< initializer.hypotheses
  FrameTrackerSettings tracker;
  ReuseConfig reuse;  ///< relocalisation after a loss (reuse.enabled, relocalization_*)
  /// map.localize_only: relocalisation never gives up for a new map.
  bool localize_only = false;
  /// Offline threaded mode (not live): a frame waits for a keyframe being mapped and is tracked
  /// against it, as in deterministic mode, instead of against the one before it (live mode never
  /// waits: a late pose costs more than a frame tracked against an older reference).
  bool wait_for_keyframes = false;
  /// Threads for the initializer's hypotheses (system.parallel_threads resolved), >= 1.
  int parallel_threads = 1;
  /// Live mode: the initializer runs on its own thread and takes the newest frame whenever it is
  /// free (the frames that come meanwhile go without a pose, as every frame before a map exists);
  /// otherwise it takes every frame on the tracking thread.
  bool async_initialization = false;
};

class TrackingStage {
 public:
  enum Timing { kPreprocess, kInitialize, kTrack, kTotal, kTimingCount };
  /// Frame records the map store can take without allocating, ensured with every keyframe, so
  /// that tracking a frame does not allocate as long as a keyframe comes at least this often.
  static constexpr std::size_t kFrameHeadroom = 1024;

  TrackingStage(const TrackingStageSettings& settings, const PyramidCamera& camera,
                FramePreprocessor& preprocessor, PyramidPool& pyramids, MapStore& store,
                MappingStage& mapping, EventSink& events);

  /// Processes one validated frame (`exposure`: the exposure time to use, 1 when unknown) and
  /// returns its event (also sent to the EventSink).
  FrameEvent process(ImageView<const std::uint8_t> image, std::int64_t index, double timestamp,
                     double exposure);

  /// Tracked frames' images (half resolution) and tracked points are published to `out` from now
  /// on (null: not). Set before the first frame.
  void setImageOutput(concurrency::LatestValue<TrackedImage>* out) { image_out_ = out; }

  /// A saved map was loaded: the first frames are looked for in it (relocalisation, as after a
  /// loss); a new map starts only when that fails for reuse.relocalization_timeout_s.
  void startInLoadedMap();

  /// For tests and diagnostics: sees, and may change, the map's answer of every relocalisation
  /// attempt before it is used (the frame's index, the window's median depth at the loss, the
  /// answer), so that the rules which check the map's pose can be run with a wrong one (on a
  /// periodic texture the map can place a frame a period off). Called on the tracking thread; set
  /// before the first frame; empty: none.
  using RelocalizationFilter =
      std::function<void(std::int64_t frame_index, double median_depth, RelocalizationResult&)>;
  void setRelocalizationFilter(RelocalizationFilter filter) {
    relocalization_filter_ = std::move(filter);
  }

  /// End of a run (the tracking thread idle): waits for an initialisation in progress on its own
  /// thread and, when it made a map, takes it over (its two keyframes' frames into the map store).
  void finish();

  TrackingStatus status() const { return status_; }
  std::int64_t initializations() const { return initializations_.load(std::memory_order_relaxed); }
  std::int64_t losses() const { return losses_.load(std::memory_order_relaxed); }
  /// Frames given to the initializer, and (live mode) those that came while it was busy with an
  /// earlier one and so went without it.
  std::int64_t initializerFrames() const {
    return initializer_frames_.load(std::memory_order_relaxed);
  }
  std::int64_t initializerBusyFrames() const {
    return initializer_busy_frames_.load(std::memory_order_relaxed);
  }
  std::int64_t relocalizationAttempts() const {
    return relocalization_attempts_.load(std::memory_order_relaxed);
  }
  /// Map answers cross-checked before a new window was built on them, and of those refused
  /// (Relocalizer::crossCheck).
  std::int64_t crossChecks() const { return cross_checks_.load(std::memory_order_relaxed); }
  std::int64_t answersRefused() const { return answers_refused_.load(std::memory_order_relaxed); }
  /// Losses after which tracking resumed in the same map (in the kept window or from a map
  /// keyframe), one per RelocalizedEvent.
  std::int64_t relocalizations() const { return relocalizations_.load(std::memory_order_relaxed); }
  std::vector<StageTiming> timings() const { return timer_.summary(); }

  /// Whether a frame tracked against the kept window after a loss fits as well as before it:
  /// at least kResumeMinInliers of its points inliers and its residual within
  /// kResumeMaxRmseGrowth of `rmse_before_loss`, or kResumeFarMinInliers within
  /// kResumeFarMaxRmseGrowth (no residual before: the inliers alone).
  static bool resumesAfterLoss(const FrameTrackingOutcome& o, double rmse_before_loss);
  /// Of two tracks of a frame after a loss that disagree, whether `a` fits the window better
  /// than `b`: smaller residuals per share of inlier points.
  static bool betterResumption(const FrameTrackingOutcome& a, const FrameTrackingOutcome& b);
  /// Whether a frame the map found near the kept window resumes there: at least
  /// kResumeConfirmedMinInliers of its points inliers and its residual within
  /// kResumeMaxRmseGrowth of `rmse_before_loss`. The map's alignment (one map keyframe's points)
  /// says the camera is near the window, not somewhere else entirely; its pose can be degrees
  /// off (live vamr_desk_loop after 40 frames of noise: 3.1-3.6 degrees from where the window's
  /// track puts the frame), and a new window built on it drifts.
  static bool resumesWhereTheMapFoundIt(const FrameTrackingOutcome& o, double rmse_before_loss);
  /// Whether a frame tracked against the kept window after a loss is close enough to resume there
  /// if the map confirms its pose (posesAgree): kPlausibleMinInliers of its points inliers
  /// and its residual within kResumeFarMaxRmseGrowth of `rmse_before_loss`.
  static bool plausibleAfterLoss(const FrameTrackingOutcome& o, double rmse_before_loss);
  /// Whether two poses of one frame agree: within kAgreeMedianDepths of `median_depth` and
  /// kAgreeDegrees of each other, both times `tolerance` (poses of consecutive frames: wider).
  static bool posesAgree(const SE3d& a_T_c_w, const SE3d& b_T_c_w, double median_depth,
                         double tolerance = 1.0);

 private:
  /// A frame for the initializer, and the initialisation it finished (the map made).
  struct InitializationFrame {
    std::unique_ptr<ImagePyramid> pyramid;
    MapperFrame info;  ///< T_c_w: the world anchor of the map it would start
    /// Frames went by since the initializer's previous frame (live mode: it was busy).
    bool after_skipped = false;
  };
  struct InitializationDone {
    MapperFrame reference;  ///< the first keyframe's frame
    MapperFrame frame;      ///< the second keyframe's frame
    InitializationOutcome outcome;
  };
  void initializeStep(std::unique_ptr<ImagePyramid> pyr, FrameEvent& frame, double exposure);
  /// One frame into the initializer (on the initializer's thread in live mode, else here); a
  /// finished initialisation becomes the mapping stage's kInitialize job (waited for). Touches
  /// only the initializer's state.
  std::optional<InitializationDone> initializeFrame(InitializationFrame& job);
  /// The finished initialisation the initializer's task handed back, if any.
  std::optional<InitializationDone> takeInitialization();
  /// Tracking from the initialisation's map on; `frame` gets its pose when it is the second
  /// keyframe's frame.
  void adoptInitialization(const InitializationDone& done, FrameEvent& frame);
  void trackStep(std::unique_ptr<ImagePyramid> pyr, FrameEvent& frame, double exposure);
  /// Tracks from now on against the newest reference the mapping stage published, if any
  /// (true); never waits for one.
  bool adoptNewestReference();
  void loseTracking(const FrameEvent& frame, const std::string& reason);
  /// While lost: looks for the frame in the map; found, tracking resumes there.
  void relocalizeStep(std::unique_ptr<ImagePyramid> pyr, FrameEvent& frame, double exposure);
  /// The frame looked for in the map (the relocaliser, with the place database's candidates).
  RelocalizationResult findInMap(const ImagePyramid& pyr, double exposure,
                                 const MappingSnapshot& snap);
  /// A frame the map found (`r`) away from the kept window, or with none: a new window on the map
  /// keyframe at the map's pose, unless the cross-check (early in the loss) refuses the answer.
  void startWindowOnAnswer(std::unique_ptr<ImagePyramid> pyr, FrameEvent& frame, double exposure,
                           double median_depth, const RelocalizationResult& r);
  /// Whether a new window may be built on the map's answer `r`: false where at least one of the
  /// other map keyframes around its pose aligns elsewhere and no fewer do so than at it
  /// (Relocalizer::crossCheck).
  bool crossCheckAnswer(const ImagePyramid& pyr, double exposure, double median_depth,
                        std::int64_t frame_index, const RelocalizationResult& r);
  /// A new window from map keyframe r.keyframe_id at the pose r found (the current one reset).
  void startWindowInMap(std::unique_ptr<ImagePyramid> pyr, FrameEvent& frame, double exposure,
                        const RelocalizationResult& r);
  /// Relocalisation gave up: a new map starts with the next initialisation.
  void startNewMap();
  /// The window goes to the map (kept while relocalising after a short loss).
  void resetWindow();
  /// A tracked frame's pose goes to the map store, the frame to the mapping stage.
  void acceptTrackedFrame(std::unique_ptr<ImagePyramid> pyr, FrameEvent& frame, double exposure,
                          const FrameTrackingOutcome& outcome);
  void resumeTracking(const FrameEvent& frame, int map_keyframe, const std::string& where);
  void publishImage(const ImagePyramid& pyr, const FrameEvent& frame, const SE3d& T_c_w);

  FramePreprocessor& preprocessor_;
  PyramidPool& pyramids_;
  MapStore& store_;
  MappingStage& mapping_;
  EventSink& events_;
  /// Helper threads for the initializer's hypotheses (null with one thread).
  std::unique_ptr<concurrency::ParallelTasks> parallel_;
  InitializerHypotheses initializer_;
  FrameTracker tracker_;
  StageTimer timer_;
  TrackingStatus status_ = TrackingStatus::Initializing;
  std::unique_ptr<ImagePyramid> init_reference_;  ///< the initializer's reference frame
  MapperFrame init_reference_info_;
  SE3d world_anchor_;  ///< world -> camera pose given to a new map's first keyframe
  std::int64_t last_tracked_index_ = -1;
  std::unique_ptr<Relocalizer> relocalizer_;  ///< null: no relocalisation (reuse off)
  RelocalizationFilter relocalization_filter_;
  double relocalization_timeout_s_ = 0.0;
  int place_candidates_ = 0;  ///< reuse.relocalization_place_candidates
  bool cross_check_ = true;   ///< reuse.relocalization_cross_check
  /// The map's answer is cross-checked (and may be refused) only within this share of the
  /// configured reuse.relocalization_timeout_s after the loss (cross_check_window_s_).
  static constexpr double kCrossCheckTimeShare = 0.5;
  double cross_check_window_s_ = 0.0;
  /// A relocalised frame resumes in the kept window only when the map keyframe it was found in
  /// is within this many median depths of the last pose (reuse.relocalization_search_radius)...
  double resume_radius_ = 0.0;
  /// ...and its tracking against the window fits as well as before the loss (resumesAfterLoss,
  /// resumesWhereTheMapFoundIt), or plausibly with the map's confirmation (plausibleAfterLoss).
  static constexpr double kResumeMinInliers = 0.7;
  static constexpr double kResumeMaxRmseGrowth = 2.0;
  /// A frame far from where the reference was taken (moved on during a gap) has larger residuals
  /// from the change of view alone: it also resumes with this many inliers within this growth.
  static constexpr double kResumeFarMinInliers = 0.9;
  static constexpr double kResumeFarMaxRmseGrowth = 3.0;
  /// A frame the map found near the window resumes there with this many inliers (the first
  /// frames after 40 frames of noise on vamr_desk_loop, live: 66-82 %, their poses right).
  static constexpr double kResumeConfirmedMinInliers = 0.6;
  /// A track the map confirms resumes with this many inliers (vamr_desk_loop after 80 black
  /// frames: 55-59 %, the camera 2.7 s on from the window's reference).
  static constexpr double kPlausibleMinInliers = 0.5;
  /// The window's track and the map's direct fit agree within this many median depths between
  /// the camera centres...
  static constexpr double kAgreeMedianDepths = 0.02;
  /// ...and this many degrees: the map's pose off by 3.1-3.6 degrees (see
  /// resumesWhereTheMapFoundIt) is not agreement.
  static constexpr double kAgreeDegrees = 1.0;
  /// A fit that resumes where the map found the frame (resumesWhereTheMapFoundIt) resumes without
  /// the map once it held for kSteadyFits attempts in a row, each within kSteadyMaxGapS of the
  /// one before, its camera centre and rotation within kSteadyAgreeFactor times posesAgree's
  /// distance and angle of the one before (the camera moves between attempts).
  static constexpr int kSteadyFits = 5;
  static constexpr double kSteadyMaxGapS = 0.5;
  static constexpr double kSteadyAgreeFactor = 2.0;
  int steady_fits_ = 0;
  SE3d steady_T_c_w_;
  double steady_timestamp_ = 0.0;
  bool wait_for_keyframes_ = false;  ///< TrackingStageSettings::wait_for_keyframes
  bool relocalizing_ = false;
  double lost_since_ = 0.0;
  bool window_kept_ = false;             ///< lost, but the window and its reference are still there
  FrameTracker::MotionState last_good_;  ///< the motion before the loss
  /// The tracking residuals of the last frames tracked (a ring), and at a loss their largest: a
  /// frame resumes only within kResumeMaxRmseGrowth of it. One frame's residual is a noisy
  /// standard (it falls after each keyframe: 4.6-6.2 before the same loss in live runs).
  std::array<double, 8> recent_rmse_{};
  std::size_t recent_rmse_next_ = 0;
  double rmse_before_loss_ = 0.0;
  // Counted on the tracking thread, read by stats() on any thread.
  concurrency::LatestValue<TrackedImage>* image_out_ = nullptr;
  TrackedImage image_scratch_;  ///< reused: publishing allocates nothing after the first frame
  std::atomic<std::int64_t> relocalization_attempts_{0};
  std::atomic<std::int64_t> relocalizations_{0};
  std::atomic<std::int64_t> cross_checks_{0};
  std::atomic<std::int64_t> answers_refused_{0};
  std::atomic<std::int64_t> initializations_{0};
  std::atomic<std::int64_t> losses_{0};
  std::atomic<std::int64_t> initializer_frames_{0};
  std::atomic<std::int64_t> initializer_busy_frames_{0};
  bool initializer_skipped_ = false;  ///< a frame went without the initializer since its last
  /// Set by the initializer's task when it finished a map, cleared when tracking took it over: no
  /// frame goes to the initializer in between.
  std::atomic<bool> initialization_pending_{false};
  /// Live mode only (null otherwise). Last member: stopped first, while what it uses is still
  /// there.
  std::unique_ptr<concurrency::BackgroundTask<InitializationFrame, InitializationDone>> init_task_;
};

}  // namespace ldsm
