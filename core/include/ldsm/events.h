// Value types the System reports to its listener. They hold copies, never references to the
// engine's internal state, so a listener may keep them and use them from any thread.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "ldsm/types.h"

namespace ldsm {

enum class TrackingStatus {
  Initializing,  ///< waiting for enough parallax to build the first map
  Tracking,      ///< the last frame was tracked
  Lost,          ///< tracking failed; the system restarts initialisation on the next frames
};

const char* toString(TrackingStatus status);

/// Every submitted frame, once processed.
struct FrameEvent {
  /// The frame's number among the frames processed (rejected ones included). In live mode the
  /// frames dropped before processing are not counted, so it falls behind the number of frames
  /// submitted (and behind a replayed sequence's file numbers); the timestamp names the frame.
  /// The other events' frame_index counts the same way.
  std::int64_t frame_index = 0;
  double timestamp = 0.0;
  TrackingStatus status = TrackingStatus::Initializing;
  bool has_pose = false;  ///< false while initialising or when lost
  Pose pose;              ///< camera-to-world at the time of processing
  bool is_keyframe = false;
  double residual_rmse = 0.0;  ///< photometric RMSE of the tracking, grey levels
};

/// A frame became a keyframe and was inserted into the optimisation window.
struct KeyframeEvent {
  int keyframe_id = 0;
  std::int64_t frame_index = 0;
  double timestamp = 0.0;
  Pose pose;  ///< camera-to-world after the window optimisation
  int active_points = 0;
};

/// The map was initialised (first two keyframes).
struct InitializedEvent {
  std::int64_t frame_index = 0;
  double timestamp = 0.0;
  int points = 0;
};

/// Tracking failed on a frame; `reason` says why.
struct TrackingLostEvent {
  std::int64_t frame_index = 0;
  double timestamp = 0.0;
  std::string reason;
};

/// A loop was closed: the keyframe `current_keyframe_id` recognised the place of
/// `matched_keyframe_id`, the Sim(3) between them was verified, and the keyframes that had left
/// the window (with their frames and points) were corrected by the pose graph.
struct LoopClosureEvent {
  int current_keyframe_id = -1;
  int matched_keyframe_id = -1;
  int inliers = 0;       ///< verified feature matches
  double scale = 1.0;    ///< relative scale of the loop constraint (drift in scale)
  double time_ms = 0.0;  ///< detection + verification + pose graph
  /// Disagreement between the loop's measured Sim(3) and the trajectory before the loop, as a
  /// squared Mahalanobis distance under the measurement's covariance (7 DoF). Below
  /// loop.correction_chi2 the drift is within the measurement's accuracy and nothing is moved.
  double drift_chi2 = 0.0;
  int corrected_keyframes = 0;  ///< 0 when the drift was not significant
};

/// Tracking was lost and the camera was found again in the existing map (relocalisation): the
/// poses that follow are in the same map frame as before the loss.
struct RelocalizedEvent {
  std::int64_t frame_index = 0;
  double timestamp = 0.0;
  int keyframe_id = -1;       ///< the new keyframe made of the relocalised frame
  int map_keyframe_id = -1;   ///< the map keyframe it was found in
  double lost_seconds = 0.0;  ///< how long tracking was lost
};

/// Map reuse brought map keyframes back into the optimisation window for a new keyframe: they
/// see its view (geometric and ORB check) and now anchor it to the existing map.
struct ReuseEvent {
  int keyframe_id = -1;  ///< the new keyframe
  std::int64_t frame_index = 0;
  double timestamp = 0.0;
  std::vector<int> reactivated;  ///< ids of the map keyframes brought back
};

/// Two maps became one: a verified loop connected the current map to an earlier one (a map
/// started after tracking was lost for longer than reuse.relocalization_timeout_s). The earlier
/// map's keyframes, frames and points were moved into the current map by the loop's Sim(3); the
/// poses reported from then on are in the frame of the first map (StampedPose::map 0) whenever
/// either of the two was connected to it.
struct MapMergeEvent {
  int merged_map = -1;  ///< the earlier map
  int into_map = -1;    ///< the current map
  int current_keyframe_id = -1;
  int matched_keyframe_id = -1;
  double scale = 1.0;         ///< scale of the earlier map relative to the current one
  int moved_keyframes = 0;    ///< keyframes moved
  bool in_map_frame = false;  ///< the merged map is connected to the first map
};

/// Receives events; every method has an empty default. In deterministic mode every call comes on
/// the caller's thread (inside submit() or finish()). In threaded mode onFrame, onTrackingLost and
/// onRelocalized come from the tracking thread, onInitialized, onKeyframe and onReuse from the
/// mapping thread (possibly at the same time as the former), and onLoopClosure and onMapsMerged
/// from the mapping thread or, for the corrections still pending at the end of a run, from the
/// thread that calls System::finish() (after the mapping thread has gone idle). Keep handlers
/// short and never call back into the System from them.
class SystemListener {
 public:
  virtual ~SystemListener() = default;
  virtual void onFrame(const FrameEvent&) {}
  virtual void onKeyframe(const KeyframeEvent&) {}
  virtual void onInitialized(const InitializedEvent&) {}
  virtual void onTrackingLost(const TrackingLostEvent&) {}
  /// When the correction has been applied (or found not significant): mapping thread, or the
  /// thread calling System::finish() in threaded mode.
  virtual void onLoopClosure(const LoopClosureEvent&) {}
  /// When map keyframes are brought back into the window (mapping thread in threaded mode).
  virtual void onReuse(const ReuseEvent&) {}
  /// When tracking resumes in the existing map after a loss (tracking thread in threaded mode).
  virtual void onRelocalized(const RelocalizedEvent&) {}
  /// When two maps were merged (see the threads above).
  virtual void onMapsMerged(const MapMergeEvent&) {}
};

}  // namespace ldsm
