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
#include <mutex>
#include <optional>
#include <vector>

#include "concurrency/background_task.h"
#include "ldsm/camera/calibration.h"
#include "ldsm/config.h"
#include "loop/bow_index.h"
#include "loop/loop_types.h"
#include "loop/loop_verification.h"
#include "loop/odometry_drift.h"
#include "loop/place_snapshot.h"
#include "loop/pose_graph.h"
#include "math/se3.h"
#include "model/marginalized_keyframe.h"

namespace ldsm::loop {

/// The verification thresholds the configuration sets (the Sim(3) inliers, the ORB matches and
/// the PnP inliers; the rest keep LoopVerificationSettings' defaults).
LoopVerificationSettings loopVerificationSettings(const LoopConfig& config);

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
  /// End of a run (and before a map is saved): processes the queued keyframes, then runs a
  /// pose-graph optimisation that is still pending (deferred, loop.pose_graph_delay_*). In
  /// threaded mode this gets loop.finish_timeout_s, plus the time a running job takes to notice
  /// the abort (the pose-graph solve and the vocabulary training poll it): then the background
  /// task is stopped, unprocessed keyframes are not looked for loops and a pending correction is
  /// not applied (unfinishedJobs() counts them). A stopped loop closer stays stopped: the
  /// keyframes of the rest of the session are refused (counted in droppedKeyframes(), warned
  /// once). Either way the task is idle afterwards, so the graph may be exported.
  void flush();
  /// Keyframes not indexed: they found the queue full (threaded mode) or came after a stop.
  std::uint64_t droppedKeyframes() const {
    return task_->dropped() + refused_after_stop_.load(std::memory_order_relaxed);
  }
  /// Jobs (keyframes, and the final pose-graph run) a timed-out flush() left unfinished.
  std::uint64_t unfinishedJobs() const { return task_->unfinished(); }
  /// The pose graph's size after the last processed keyframe (any thread).
  std::int64_t graphVertices() const { return graph_vertices_.load(std::memory_order_relaxed); }
  std::int64_t graphEdges() const { return graph_edges_.load(std::memory_order_relaxed); }
  /// A new map after tracking was lost: its keyframes are not chained to the old ones.
  void startNewMap() { new_map_.store(true); }
  // ---- Saved maps (call while the task is idle: after flush(), or before the first keyframe)
  /// The pose graph's edges between keyframes of `ids`, plus odometry edges chaining `window`
  /// (the window's keyframes with their poses, in order) to the newest vertex; and the
  /// vocabulary (null before the first online training).
  struct GraphExport {
    std::vector<PoseGraphEdge> edges;
    std::shared_ptr<const Vocabulary> vocabulary;
  };
  GraphExport exportGraph(const std::vector<int>& ids,
                          const std::vector<std::pair<int, Sim3d>>& window) const;
  /// Starts from a saved map (before the first keyframe): its vertices (by increasing id), edges,
  /// vocabulary (may be null: trained online later) and the kept keyframes' features, all in
  /// the first map; the next keyframes start a chain of their own, tied to the saved one by the
  /// map keyframes brought back into their window and by loops.
  void importMap(const std::vector<std::pair<int, Sim3d>>& vertices,
                 const std::vector<PoseGraphEdge>& edges,
                 std::shared_ptr<const Vocabulary> vocabulary,
                 const std::vector<std::shared_ptr<const MarginalizedKeyframe>>& data);
  /// Mapping thread: the keyframe no longer keeps its features in the map (the map's budget): it
  /// stays in the pose graph but is no place to be found (taken out before the next keyframe).
  void forget(int keyframe_id);
  /// Place recognition for relocalisation: the vocabulary and the indexed keyframes as of the
  /// last processed keyframe (any thread; never waits for the loop task's work).
  std::shared_ptr<const PlaceSnapshot> places() const;

 private:
  std::optional<LoopCorrection> process(LoopJob& job, const std::atomic<bool>& abort);
  /// Adds the keyframe's vertex, its odometry edge and its constraints to map keyframes brought
  /// back into the window; returns how many of the latter show significant drift.
  int addToGraph(const LoopJob& job, bool new_map);
  /// Adds the relative-pose constraints of a map keyframe brought back into the window; returns
  /// whether they disagree with the graph beyond the odometry's uncertainty.
  bool addReuseConstraints(const LoopJob& job, const PoseGraphEdge* odometry);
  std::optional<DetectedLoop> closeLoop(int id, std::optional<MapMerge>& merge);
  /// The map a keyframe's map was merged into (transitively).
  int mapRoot(int map) const;
  /// Moves the candidate's map into the current keyframe's frame by the loop's Sim(3).
  MapMerge mergeMaps(int id, int candidate, const Sim3d& S_current_candidate);
  /// A significant constraint arrived: the pose graph runs once it is due.
  void markPending();
  bool poseGraphDue() const;
  /// Optimises the graph with the newest keyframe fixed; fills `out` with the corrected poses and
  /// the pending loops.
  void optimizePending(LoopCorrection& out, const std::atomic<bool>& abort);
  /// Information of a constraint from the window between two keyframes at nearly one place: one
  /// odometry step of the drift model at the chain's mean step length.
  Matrix7d windowEdgeInformation(const Sim3d& S) const;
  void connectCovisible(int a, int b, int shared_points);
  /// A map keyframe the window held with the newest keyframe (its links) that is `candidate`
  /// itself or covisible with it; -1 if none.
  int heldNeighbour(int candidate) const;
  /// Folds the keyframes no longer needed as vertices (culled or forgotten: no place to be found,
  /// no data in the map) into a neighbour (PoseGraph::foldVertex) once
  /// loop.pose_graph_recent_keyframes keyframes were processed after they retired (never the
  /// newest vertex, which the next keyframe's odometry edge starts from): the graph stays as
  /// large as the map plus the recent trajectory.
  void foldRetired();
  /// The vertex a keyframe is folded into: the neighbour of the most certain edge (largest
  /// information determinant; -1: no edges).
  int foldAnchor(int id) const;
  /// Publishes the place snapshot after keyframe `id` was indexed (or removed again).
  void publishPlaces(int id);

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
  std::atomic<std::int64_t> graph_vertices_{0};
  std::atomic<std::int64_t> graph_edges_{0};
  // Used only by the background task.
  BowIndex index_;
  std::map<int, KeyframeFeatures> features_;
  std::map<int, ChainPosition> chain_;
  PoseGraph graph_;
  int last_id_ = -1;
  SE3d last_T_w_c_;
  std::vector<int> fixed_ids_;  ///< vertices held by the last correction
  LoopVerificationSettings verification_;
  /// The links of the keyframe that left the window last (its relative poses to the keyframes
  /// still in the window then): the next keyframe's odometry edge is measured there.
  std::vector<KeyframeLink> last_links_;
  /// Keyframes sharing more than loop.covisible_shared_points points (not loop candidates of
  /// each other).
  std::map<int, std::vector<int>> covisible_;
  /// Vertices waiting to be folded (foldRetired) with the processed-keyframe count when they
  /// retired, and the folds not yet published.
  std::vector<std::pair<int, int>> retired_;
  std::vector<std::pair<int, int>> folded_;
  // The deferred pose graph: significant loops waiting for it, and when constraints arrived
  // (in processed keyframes).
  std::vector<DetectedLoop> pending_loops_;
  int pending_reuse_ = 0;
  int pending_first_ = -1;
  int pending_last_ = -1;
  int processed_ = 0;
  int chain_base_ = 0;  ///< chain step of a loaded map's last keyframe
  // Maps (a new one after tracking was lost for good) and which were merged into which.
  std::map<int, int> map_of_;  ///< keyframe id -> the map it was made in
  std::vector<int> map_parent_{0};
  // Place recognition for relocalisation: each indexed keyframe's BoW vector as last published
  // (rebuilt when the vocabulary changes), and the snapshot (mutex held only to swap it).
  std::map<int, std::shared_ptr<const BowVector>> place_bows_;
  std::mutex forget_mutex_;
  std::vector<int> forget_;  ///< keyframes to take out of the index (forget())
  std::uint64_t place_generation_ = 0;
  mutable std::mutex places_mutex_;
  std::shared_ptr<const PlaceSnapshot> places_;
  // Last: stopped (joined) first on destruction, before the state above goes away.
  std::atomic<std::uint64_t> refused_after_stop_{0};  ///< keyframes after a timed-out flush()
  std::unique_ptr<concurrency::BackgroundTask<LoopJob, LoopCorrection>> task_;
};

}  // namespace ldsm::loop
