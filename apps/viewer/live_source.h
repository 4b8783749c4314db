// Snapshots of a running System for the viewer: value copies of its published state (trajectory,
// keyframes, map points, latest pose and image, stats), read on the viewer's thread. As a
// listener it remembers the keyframes' times (to place loop edges) and the keyframes map reuse
// brought back; its handlers only take a short lock of its own, on the mapping thread.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "ldsm/events.h"
#include "ldsm/system.h"
#include "snapshot.h"

namespace ldsm::viewer {

class LiveSource : public SnapshotSource, public SystemListener {
 public:
  /// `source`: the dataset or device shown on the page; `mode`: "live", "offline", ...
  LiveSource(const System& system, std::string source, std::string mode);

  ViewerSnapshot snapshot(bool with_points) override;
  /// The run is over: pages are told no more updates will come.
  void markFinished() { finished_.store(true); }

  void onKeyframe(const KeyframeEvent& e) override;
  void onReuse(const ReuseEvent& e) override;

 private:
  int keyframeIndex(int id, const std::vector<double>& keyframe_times) const;

  const System& system_;
  std::string source_;
  std::string mode_;
  std::atomic<bool> finished_{false};
  mutable std::mutex mutex_;
  std::map<int, double> keyframe_times_;  ///< keyframe id -> timestamp
  std::vector<int> reactivated_ids_;      ///< map keyframes brought back, in order
  // Frame rate over the last second (publisher thread only).
  std::chrono::steady_clock::time_point rate_time_{};
  std::int64_t rate_frames_ = -1;
  double fps_ = 0.0;
  std::int64_t point_count_ = 0;  ///< map points in the last snapshot that had them
};

/// Resident memory of this process, MB (0 when unknown).
double currentRssMb();

/// Poses as kPoseStride floats each.
void appendPose(const Pose& pose, std::vector<float>& out);

}  // namespace ldsm::viewer
