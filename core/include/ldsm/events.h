// Value types the System reports to its listener. They hold copies, never references to the
// engine's internal state, so a listener may keep them and use them from any thread.
#pragma once

#include <cstdint>
#include <string>

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

/// Receives events; every method has an empty default. In deterministic mode every call comes on
/// the caller's thread; in threaded mode onFrame / onInitialized / onTrackingLost come from the
/// tracking thread and onKeyframe from the mapping thread (possibly at the same time). Keep
/// handlers short and never call back into the System from them.
class SystemListener {
 public:
  virtual ~SystemListener() = default;
  virtual void onFrame(const FrameEvent&) {}
  virtual void onKeyframe(const KeyframeEvent&) {}
  virtual void onInitialized(const InitializedEvent&) {}
  virtual void onTrackingLost(const TrackingLostEvent&) {}
};

}  // namespace ldsm
