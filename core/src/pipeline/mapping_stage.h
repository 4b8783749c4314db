// The mapping stage: everything that changes the window, as jobs over one queue (a
// concurrency::BackgroundTask): inline on the caller's thread in deterministic mode, on the
// mapping thread otherwise, through the very same code. A job is a tracked frame (trace its
// pixels into the window's immature points), a keyframe (one integrateKeyframe() path), the
// initialisation of a new map, or a reset after tracking was lost. After every change the stage
//  * describes the keyframes that left the window (ORB), keeps them in the map store (or only
//    their pose when they were redundant with the map) and hands them to loop closure,
//  * applies the loop corrections that arrived (its safe point),
//  * brings map keyframes that see the newest keyframe back into the window (map reuse,
//    reuse/reactivation_search.h) and takes back those that no longer fit,
//  * publishes a tracking reference for the newest keyframe (ReferenceExchange),
//  * publishes a snapshot of the window for queries (MappingSnapshot), and
//  * reports keyframe and initialisation events (EventSink).
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "backend/mapper.h"
#include "concurrency/background_task.h"
#include "concurrency/latest_value.h"
#include "features/orb_extractor.h"
#include "frontend/coarse_tracker.h"
#include "image/pyramid_pool.h"
#include "ldsm/config.h"
#include "loop/loop_closer.h"
#include "map/map_store.h"
#include "mapfile/map_data.h"
#include "pipeline/calibration_history.h"
#include "pipeline/event_sink.h"
#include "pipeline/reference_exchange.h"
#include "pipeline/stage_timer.h"
#include "reuse/reactivation_search.h"
#include "reuse/resting_keyframes.h"

namespace ldsm {

/// One piece of mapping work.
struct MappingJob {
  enum class Kind { kTrace, kKeyframe, kInitialize, kReset, kRelocalize, kNewMap };
  Kind kind = Kind::kTrace;
  std::unique_ptr<ImagePyramid> pyramid;  ///< the frame (kTrace, kKeyframe; kInitialize: last)
  MapperFrame info;
  // kInitialize only: the initializer's result and its reference frame.
  InitializationResult initialization;
  std::unique_ptr<ImagePyramid> reference_pyramid;
  MapperFrame reference_info;
  // kRelocalize only: the map keyframe the frame was found in.
  int anchor_keyframe = -1;
};

/// Map reuse found the window drifted off the map beyond its optimisation's reach
/// (MappingStage::checkDriftOffTheMap): where the map puts the newest keyframe.
struct ReanchorRequest {
  int anchor_keyframe = -1;  ///< the map keyframe a new window starts from (-1: none)
  SE3d T_newest_w_window;    ///< the newest keyframe's pose in the window
  SE3d T_newest_w_map;       ///< where the map keyframes put it
};

/// What queries read of the mapping (published after every job that changed the window).
struct MappingSnapshot {
  std::vector<MapPoint> active_points;  ///< the window's points, world coordinates
  int active_point_count = 0;
  double radial_estimate = 0.0;
  double radial_applied = 0.0;
  /// The refinement's applied correction (radial k, focal log-scale, cx, cy: what a saved map
  /// records in CALB and CALR).
  CalibVector calibration_applied = CalibVector::Zero();
  CalibrationStats calibration;
  /// The refinement's history (pipeline/calibration_history.h; never null once published).
  std::shared_ptr<const std::vector<CalibrationSample>> calibration_history;
  bool has_window = false;
  SE3d newest_T_c_w;            ///< the newest keyframe's pose (or the last one, no window)
  std::vector<int> window_ids;  ///< the active keyframes (or the last ones, no window)
  /// Of the window's points seen from the newest keyframe; before any window, a loaded map's
  /// (continueAfterLoadedMap), else 1.
  double median_depth = 1.0;
  std::vector<int> reactivated;  ///< map keyframes in the window
  ReuseStats reuse;
};

/// How the last initialisation or relocalisation job ended.
struct InitializationOutcome {
  bool ok = false;
  int points = 0;
  int keyframe_id = -1;  ///< the second keyframe (the first has keyframe_id - 1)
  SE3d T_c_w;            ///< the second keyframe's pose
  AffineLight aff;
};

/// The mapping stage's settings: its sections of the configuration and what is derived from them.
struct MappingStageSettings {
  MapperSettings mapper;
  CoarseTrackerSettings tracker;  ///< of the tracking references it prepares
  ReuseConfig reuse;
  int queue_capacity = 4;             ///< system.mapping_queue
  int loop_corners = 400;             ///< loop.corners_per_keyframe
  float loop_corner_min_score = 9.f;  ///< loop.corner_min_score
  /// map.localize_only: keyframes that leave the window are dropped; the map never changes.
  bool localize_only = false;
  /// Threads for the window's linearisation (system.parallel_threads resolved for mapping), >= 1.
  int parallel_threads = 1;
};

class MappingStage {
 public:
  /// kReuse (the search for map keyframes to bring back) and kLoop (loop closure's share done on
  /// this thread: all of it in deterministic mode) are parts of kMapping.
  enum Timing { kTrace, kMapping, kReuse, kLoop, kTimingCount };

  /// `loop_closer` may be null (loop closure off). `inline_mode`: deterministic.
  MappingStage(const MappingStageSettings& settings, const PyramidCamera& camera,
               PyramidPool& pyramids, MapStore& store, EventSink& events,
               loop::LoopCloser* loop_closer, bool inline_mode);
  ~MappingStage();
  MappingStage(const MappingStage&) = delete;
  MappingStage& operator=(const MappingStage&) = delete;

  /// Queues a job or runs it now (deterministic mode). A full queue drops an ordinary frame's
  /// tracing job; the other jobs wait for room.
  void submit(MappingJob job);
  /// Waits until every submitted job is done.
  void waitIdle();
  /// Jobs waiting for the mapping thread (a snapshot).
  std::size_t backlog() const { return task_->backlog(); }
  /// Tracking side, before submitting a keyframe job: its reference is on its way.
  void setKeyframeInFlight() { keyframe_in_flight_.store(true, std::memory_order_release); }
  /// The mapping thread (threaded mode), e.g. to pin it to a CPU.
  std::optional<std::thread::native_handle_type> threadHandle() { return task_->workerHandle(); }
  /// A keyframe job was submitted and its reference is not published yet.
  bool keyframeInFlight() const { return keyframe_in_flight_.load(std::memory_order_acquire); }
  /// Whether map reuse found the window drifted off the map (checkDriftOffTheMap) since the last
  /// call, and where the map puts it: the tracking stage then starts a new window from the map.
  bool takeReanchorRequest(ReanchorRequest& out) {
    return reanchor_.readNew(out) && out.anchor_keyframe >= 0;
  }
  /// Waits while a keyframe is in flight.
  void waitForKeyframe();
  ReferenceExchange& references() { return references_; }
  /// Place recognition over the map (null without loop closure); any thread.
  std::shared_ptr<const loop::PlaceSnapshot> places() const {
    return loop_closer_ ? loop_closer_->places() : nullptr;
  }
  /// How the last initialisation or relocalisation job ended (read after waitIdle()).
  const InitializationOutcome& lastInitialization() const { return init_outcome_; }

  /// For a saved map (the stage idle, e.g. after finish()): the window's keyframes as the map
  /// would keep them if they left it now; the window is unchanged.
  std::vector<MarginalizedKeyframe> windowForMap();
  /// A loaded map's keyframes keep their ids: the next keyframe is `next_keyframe_id`.
  /// It was measured with the refinement's correction `calibration` (focal and principal point):
  /// the window starts with it. Until a window measures its own, the snapshot's median depth
  /// (the unit of relocalisation's search radius and of whether two poses agree) is the map's
  /// `median_depth` (map/map_depth.h), when it has points.
  void continueAfterLoadedMap(int next_keyframe_id, const MapCalibration& calibration,
                              std::optional<double> median_depth);

  /// End of a run: waits for the loop task, applies what it found and publishes the window.
  void finish();

  std::shared_ptr<const MappingSnapshot> snapshot() const;
  std::vector<StageTiming> timings() const { return timer_.summary(); }
  std::int64_t keyframes() const { return keyframes_.load(std::memory_order_relaxed); }

 private:
  friend struct MappingStageAccess;  // the unit tests
  struct Done {};
  std::optional<Done> process(MappingJob& job);
  void trace(MappingJob& job);
  void integrateKeyframe(MappingJob& job);
  void initialize(MappingJob& job);
  void relocalize(MappingJob& job);
  /// The window (re)started with the newest keyframe (initialisation, relocalisation): its outcome,
  /// tracking reference and snapshot are published, then the listener hears of it (initialised
  /// first, when `initialized`), with `points` the points it sees.
  void startWindow(const MapperFrame& info, int points, bool initialized);
  void reset();
  /// Hands the window's output to the map store and loop closure.
  void publishMap(MapUpdate&& update);
  /// What the map keeps of a keyframe that leaves the window (its well-measured points).
  MarginalizedKeyframe asMapKeyframe(const MarginalizedKeyframe& kf) const;
  /// reuse.max_map_keyframes: the most redundant kept keyframes keep only their poses.
  void keepMapBudget();
  /// The corrections loop closure has published so far (applyCorrections).
  void applyLoopCorrections();
  /// Merges maps a loop connected, moves the map store's keyframes, frames and points (never the
  /// window) and the reactivated keyframes with them, and reports each loop.
  void applyCorrections(const std::vector<loop::LoopCorrection>& corrections);
  /// A loop connected an earlier map to the current one; returns the keyframes moved.
  int mergeMaps(const loop::MapMerge& merge);
  void publishReference();
  void publishSnapshot();
  /// ORB descriptors at the corners of a described keyframe (drops the ones without, and the
  /// image).
  void describeOrb(MarginalizedKeyframe& kf);
  /// Map reuse after a keyframe (mapping_stage_reuse.cpp): take back reactivated keyframes that
  /// no longer fit, bring back those that see the newest keyframe.
  void reuseMap(int newest_frame_index, double newest_timestamp);
  void takeBackMisfits();
  /// Takes reactivated keyframe `id` out of the window (it rests after a second time soon).
  void takeOut(int id);
  /// The reactivated keyframes that lost most of the view they came back for, as (inliers in the
  /// newest keyframe, id), weakest first (updates each one's peak).
  std::vector<std::pair<int, int>> replaceableReactivated();
  ReuseView reuseView(const WindowKeyframe& newest);
  /// With no map keyframe in the window and none accepted: do map keyframes that fit but lie
  /// beyond the basin agree that the window drifted off the map (reuse/drift_consensus.h), and
  /// pass every check from where they put it? Then a re-anchoring is requested.
  /// Only when driftCheckDue(): it needs every candidate's direct check.
  bool checkDriftOffTheMap(const ReuseView& view, const std::vector<ReuseCheck>& checks);
  /// The conditions of checkDriftOffTheMap that do not depend on the candidates: re-anchoring
  /// is on, something could be taken, no map keyframe held in the window fits, and the window
  /// was on the map a few keyframes ago.
  bool driftCheckDue(int newest_id, bool can_take) const;
  std::vector<int> reuseExclusions(int newest_id);
  /// Something found could come back: the window has room for a map keyframe, or holds a
  /// weakened one (`held`, replaceableReactivated()) that may be replaced.
  bool canTake(int room, const std::vector<std::pair<int, int>>& held) const;
  /// Reactivates the accepted candidates while there is room (or a weak one to replace). A
  /// candidate whose direct check was left out (`direct_skipped`) gets it here when something
  /// could come back (canTake), in the candidates' order, until nothing more can be taken.
  void bringBack(const ReuseView& view, std::vector<ReuseCheck>& checks,
                 std::vector<std::pair<int, int>>& held, int room, ReuseEvent& event);
  /// reuse.trial_check: keeps the event's keyframes a trial optimisation confirms.
  void confirmByTrial(ReuseEvent& event);

  MappingStageSettings settings_;
  PyramidPool& pyramids_;
  MapStore& store_;
  EventSink& events_;
  loop::LoopCloser* loop_closer_;
  /// Helper threads for the window's linearisation (null with one thread).
  std::unique_ptr<concurrency::ParallelTasks> parallel_;
  Mapper mapper_;
  ReferenceExchange references_;
  /// The dense depth maps every tracking reference is built in (publishReference), shared by the
  /// coarse trackers in circulation, which keep only their point lists.
  DepthMapCanvas depth_canvas_;
  StageTimer timer_;
  std::vector<DepthPoint> depth_points_;
  /// Most points of a tracking reference with map keyframes' points in it (referencePointBudget
  /// of reuse.reference_point_ratio; 0: no limit).
  int reference_point_budget_ = 0;
  bool describe_;     ///< keyframes leaving the window are described (loop closure or reuse)
  bool inline_mode_;  ///< deterministic: jobs run in the submitting thread
  std::unique_ptr<OrbExtractor> orb_;
  std::vector<std::uint32_t> orb_kept_;
  /// ORB descriptions of window keyframes made for the reuse search, kept until the keyframe
  /// leaves the window and is described for the map: the same image and corners give the same
  /// descriptors, so they are not computed twice.
  struct OrbDescription {
    int keyframe_id = -1;
    std::vector<Eigen::Vector2f> corners;  ///< the corners described
    std::vector<OrbDescriptor> descriptors;
    std::vector<std::uint32_t> kept;  ///< indices into corners of the described ones
  };
  std::vector<OrbDescription> window_descriptions_;
  /// More than a window ever holds; the oldest go first.
  static constexpr std::size_t kMaxWindowDescriptions = 64;
  std::vector<float> idepths_;  ///< scratch of medianDepth
  static double medianDepth(const std::vector<DepthPoint>& points, std::vector<float>& scratch);
  std::unique_ptr<ReactivationSearch> reuse_;
  ReuseStats reuse_stats_;
  /// Per reactivated keyframe: the most inliers it has had in a newest keyframe (how well it
  /// fitted the view it was brought back for).
  std::vector<std::pair<int, int>> reactivated_peak_;  // (id, inliers)
  RestingKeyframes resting_;  ///< taken out of the window or turned down by the trial
  concurrency::LatestValue<ReanchorRequest> reanchor_;
  int last_on_map_id_ = -1;  ///< the newest keyframe whose window held a map keyframe
  static constexpr std::size_t kDriftScenePoints = 300;  ///< scene points the drift is measured on
  int last_left_id_ = -1;
  double median_depth_ = 1.0;
  CalibrationHistory calibration_history_;  ///< written by publishSnapshot() only
  std::atomic<bool> keyframe_in_flight_{false};
  std::atomic<std::int64_t> keyframes_{0};
  InitializationOutcome init_outcome_;
  mutable std::mutex snapshot_mutex_;  ///< held only to swap the pointer
  std::shared_ptr<const MappingSnapshot> snapshot_;
  // Last: stopped (joined) first on destruction, before the state above goes away.
  std::unique_ptr<concurrency::BackgroundTask<MappingJob, Done>> task_;
};

}  // namespace ldsm
