// The map store: every keyframe ever created (pose kept up to date while it is in the window, final
// once it leaves), every processed frame's pose relative to its reference keyframe, and the
// points that left the window. Thread-safe: tracking, mapping and readers of results use it from
// different threads.
#pragma once

#include <cstdint>
#include <map>
#include <mutex>
#include <vector>

#include "ldsm/math/sim3.h"
#include "ldsm/types.h"
#include "model/map_records.h"

namespace ldsm {

class MapStore {
 public:
  /// Adds or updates a keyframe's pose.
  void setKeyframe(const KeyframeRecord& record);
  void addFrame(const FrameRecord& record);
  void addPoints(const std::vector<HostedPoint>& points);
  /// Loop closure: moves the given keyframes to their corrected Sim(3) world-from-camera poses,
  /// with their frames and the points they hosted. Returns the number of keyframes moved.
  int applyCorrection(const std::map<int, Sim3d>& S_world_camera);

  /// World pose of every recorded frame, composed with the current keyframe poses.
  Trajectory frameTrajectory() const;
  Trajectory keyframeTrajectory() const;
  std::vector<MapPoint> points() const;
  std::size_t keyframeCount() const;
  bool hasKeyframe(int id) const;

 private:
  mutable std::mutex mutex_;
  std::vector<KeyframeRecord> keyframes_;  ///< indexed by id
  std::vector<FrameRecord> frames_;
  std::vector<HostedPoint> points_;
};

}  // namespace ldsm
