// The loop-closing module: keyframes that leave the odometry window are described (ORB at their
// corners, on the mapping thread), then in a low-priority background task (inline in
// deterministic mode) they are added to the bag-of-words index and the Sim(3) pose graph,
// queried for earlier places, verified geometrically, and a verified loop optimises the graph.
// The mapper takes the resulting corrections at a safe point and applies them to the keyframes
// outside the window (the window itself is never touched; the newest graph vertex is held
// fixed, so the window stays consistent with the corrected map).
#pragma once

#include <atomic>
#include <map>
#include <memory>
#include <optional>
#include <vector>

#include "concurrency/background_task.h"
#include "ldsm/camera/calibration.h"
#include "ldsm/config.h"
#include "loop/bow_index.h"
#include "loop/loop_types.h"
#include "loop/loop_verification.h"
#include "loop/odometry_drift.h"
#include "loop/pose_graph.h"
#include "math/se3.h"
#include "model/marginalized_keyframe.h"

namespace ldsm::loop {

/// One keyframe handed to the background task: the keyframe as it left the window.
using LoopJob = MarginalizedKeyframe;

class LoopCloser {
 public:
  /// `inline_mode`: process every keyframe synchronously (deterministic runs).
  LoopCloser(const LoopConfig& config, const PinholeIntrinsics& camera, bool inline_mode);
  ~LoopCloser();
  LoopCloser(const LoopCloser&) = delete;
  LoopCloser& operator=(const LoopCloser&) = delete;

  /// Mapping thread: `kf` left the window, described (corners with ORB descriptors and depths;
  /// its points and image are not needed); queued for the task. A culled keyframe (redundant with
  /// the map) looks for loops but is not kept as a place to be found.
  void keyframeLeftWindow(MarginalizedKeyframe&& kf);
  /// Mapping thread, at a safe point: corrections published since the last call.
  std::vector<LoopCorrection> takeCorrections() { return task_->tryTakeResults(); }
  /// Waits (bounded) until every queued keyframe is processed; end of a run.
  void waitIdle();
  std::uint64_t droppedKeyframes() const { return task_->dropped(); }
  /// A new map after tracking was lost: its keyframes are not chained to the old ones.
  void startNewMap() { new_map_.store(true); }

 private:
  std::optional<LoopCorrection> process(LoopJob& job, const std::atomic<bool>& abort);
  void addToGraph(const LoopJob& job, bool new_map);
  std::optional<LoopCorrection> closeLoop(int id, const std::atomic<bool>& abort);

  /// Where a keyframe sits on the odometry chain: keyframe steps and distance (map units) from
  /// the chain's start.
  struct ChainPosition {
    int step = 0;
    double path = 0.0;
  };
  /// Steps put between two maps (tracking lost in between): no odometry connects them.
  static constexpr int kDisconnectedSteps = 1000000;

  LoopConfig config_;
  PinholeIntrinsics camera_;
  OdometryDriftModel drift_;
  std::atomic<bool> new_map_{false};
  // Used only by the background task.
  BowIndex index_;
  std::map<int, KeyframeFeatures> features_;
  std::map<int, ChainPosition> chain_;
  PoseGraph graph_;
  int last_id_ = -1;
  SE3d last_T_w_c_;
  int fixed_id_ = -1;
  LoopVerificationSettings verification_;
  // Last: stopped (joined) first on destruction, before the state above goes away.
  std::unique_ptr<concurrency::BackgroundTask<LoopJob, LoopCorrection>> task_;
};

}  // namespace ldsm::loop
