// The map store: every keyframe ever created (pose kept up to date while it is in the window, final
// once it leaves), every processed frame's pose relative to its reference keyframe, the points
// that left the window, and for map reuse what a keyframe that left the window keeps (its points
// with depths and pattern intensities, its corners with ORB descriptors), the covisibility graph
// and a spatial index of keyframe centres. Thread-safe: tracking, mapping and readers of results
// use it from different threads. The frame records are an append-only log written by tracking
// alone: addFrame() takes no lock, and readers (frameTrajectory) never make tracking wait. With a
// bounded frame history (setFrameHistory) the mapping stage retires the oldest frames: their
// poses, composed with the keyframe poses of that moment, wait for takeRetiredFrames() and leave
// memory, so that a long run's memory does not grow with the trajectory. The rest is guarded by
// one mutex, never held while the window is optimised. The queries
// (frameTrajectory, keyframeTrajectory, points, the counts) take no lock either: every change
// publishes an immutable MapSnapshot, which they read. The points are kept in immutable blocks
// (one per addPoints call) that snapshots share, and so are the keyframe poses (KeyframeTable); a
// correction or a cull copies only the blocks it changes, so publishing costs a copy of block
// pointers, not of the map.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

#include "concurrency/append_only_log.h"
#include "ldsm/types.h"
#include "map/covisibility_graph.h"
#include "map/keyframe_table.h"
#include "map/map_frames.h"
#include "map/spatial_index.h"
#include "math/sim3.h"
#include "model/map_records.h"
#include "model/marginalized_keyframe.h"

namespace ldsm {

/// What the map store's queries read: the state after one change, never modified afterwards.
struct MapSnapshot {
  using PointBlock = std::vector<HostedPoint>;
  std::shared_ptr<const KeyframeTable> keyframes;  ///< by id, its blocks shared with the store
  std::vector<std::shared_ptr<const PointBlock>> points;         ///< in the order they were added
  std::size_t keyframe_count = 0;
  std::size_t data_keyframes = 0;
  std::size_t point_count = 0;
  std::size_t data_bytes = 0;
  MapFrames maps;  ///< which map each keyframe's map belongs to, and the reported frame
};

/// The first map (with every map merged into it) as values: what a saved map holds of the store.
/// Poses and points are in the store's internal frame; S_report_world maps them into the frame
/// poses are reported in.
struct StoredMap {
  std::vector<KeyframeRecord> keyframes;                          ///< by increasing id
  std::vector<std::shared_ptr<const MarginalizedKeyframe>> data;  ///< by increasing id
  std::vector<HostedPoint> points;
  std::vector<std::array<int, 3>> covisibility;  ///< (a, b, weight), a < b
  Sim3d S_report_world;
};

class MapStore {
 public:
  MapStore();
  /// Adds or updates a keyframe's pose.
  void setKeyframe(const KeyframeRecord& record);
  /// Adds or updates several keyframes' poses (one snapshot published).
  void setKeyframes(const std::vector<KeyframeRecord>& records);
  /// Tracking thread only (the log's one writer): records a tracked frame; lock-free.
  void addFrame(const FrameRecord& record);
  /// Tracking thread only: makes room for `n` more frame records, so that addFrame() does not
  /// allocate before them (called with each keyframe).
  void reserveFrames(std::size_t n);
  /// Keep at least the newest `frames` frame records in memory (0: every one, the default).
  /// Set before the first frame.
  void setFrameHistory(std::size_t frames);
  /// Mapping thread: retires the frame records beyond the history (in whole chunks of the log,
  /// kFrameChunk): their world poses, composed with the keyframe poses now, wait for
  /// takeRetiredFrames(); later corrections no longer move them. Never makes tracking wait.
  /// When more than kRetiredBacklog chunks wait untaken, the oldest are dropped and counted.
  /// Returns the number of frames retired.
  std::size_t retireFrames();
  /// The retired frames' poses not taken yet, oldest first (frameTrajectory() continues them).
  Trajectory takeRetiredFrames();
  /// Frames retired so far, and of those dropped because nobody took them.
  std::int64_t retiredFrameCount() const;
  std::int64_t lostRetiredFrameCount() const;
  static constexpr std::size_t kFrameChunk = 4096;
  static constexpr std::size_t kRetiredBacklog = 4;
  void addPoints(const std::vector<HostedPoint>& points);
  /// Loop closure: moves the given keyframes to their corrected Sim(3) world-from-camera poses,
  /// with their frames and the points they hosted. Returns the number of keyframes moved.
  /// A keyframe that no correction lists moves with the keyframe it follows (transitively), if
  /// that one moves.
  int applyCorrection(const std::map<int, Sim3d>& S_world_camera);
  /// Loop closure folded keyframes out of its pose graph: each (keyframe, followed) keyframe
  /// moves with the one it follows from now on (its pose relative to it kept).
  void followKeyframes(const std::vector<std::pair<int, int>>& folded);
  /// Tracking was lost for good: the keyframes from now on belong to a new map (its number).
  int startNewMap();
  /// The map new keyframes belong to.
  int currentMap() const;
  /// A loop connected map `from` to map `into`: `from`'s keyframes move to the given poses (by
  /// S_into_from, see applyCorrection) and the two are one map from now on. Returns the number
  /// of keyframes moved.
  int mergeMaps(int from, int into, const Sim3d& S_into_from,
                const std::map<int, Sim3d>& S_world_camera);
  /// The first map as values (StoredMap).
  StoredMap firstMap() const;
  /// Starts from a saved map (an empty store only): its keyframes, data, points and covisibility
  /// become the first map, in the frame poses are reported in.
  void loadMap(const StoredMap& map);
  /// Whether a map is connected to the first map (its poses are reported in its frame).
  bool inFirstMap(int map) const;
  /// Whether a keyframe belongs to the current map (or one merged with it): only those share the
  /// window's frame. The reuse queries below return only such keyframes.
  bool inCurrentMap(int keyframe_id) const;

  /// The state after the latest change; never waits for a writer.
  std::shared_ptr<const MapSnapshot> snapshot() const;
  /// World pose of every recorded frame not retired, composed with the current keyframe poses.
  Trajectory frameTrajectory() const;
  Trajectory keyframeTrajectory() const;
  /// `extra` more elements of capacity are reserved, for a caller that appends (one allocation
  /// of the final size instead of a copy into a doubled one).
  std::vector<MapPoint> points(std::size_t extra = 0) const;
  std::size_t keyframeCount() const;
  bool hasKeyframe(int id) const;
  /// The keyframe's current pose record (id -1 when unknown).
  KeyframeRecord keyframe(int id) const;

  // ---- What map reuse needs ----
  /// Keeps what a keyframe that left the window needs for reuse (its image is not kept).
  void setKeyframeData(std::shared_ptr<const MarginalizedKeyframe> data);
  /// The kept data of a keyframe, null when none is kept (still in the window, or culled).
  std::shared_ptr<const MarginalizedKeyframe> keyframeData(int id) const;
  /// Drops a redundant keyframe's data and the points it hosted; its pose stays (frames were
  /// tracked against it). It leaves the covisibility graph for good.
  void cullKeyframe(int id);
  /// Adds `weight` to the covisibility edge a - b. A culled keyframe has no place in the graph:
  /// an edge to one (a loop found from a keyframe culled before the loop closer saw it) is left
  /// out, so the graph stays as large as the map.
  void connect(int a, int b, int weight = 1);
  /// Keyframes with data within `hops` covisibility edges of `start`.
  std::vector<int> covisibleNeighbourhood(const std::vector<int>& start, int hops,
                                          std::size_t max_count) const;
  /// Keyframes with data whose camera centre is within `radius` of `centre`.
  std::vector<int> keyframesNear(const Eigen::Vector3d& centre, double radius) const;
  /// The kept keyframe (data) of the current map that is most redundant: the one nearest to
  /// another kept keyframe whose optical axis is within `max_angle_rad` of its own (ties: the
  /// older), leaving out `exclude`; -1 when there is none.
  int mostRedundantKeyframe(double max_angle_rad, const std::vector<int>& exclude) const;
  /// Keyframes whose data is kept, and the bytes that data and the points take.
  std::size_t dataKeyframeCount() const;
  std::size_t pointCount() const;
  std::size_t dataBytes() const;

 private:
  static std::size_t bytesOf(const MarginalizedKeyframe& kf);
  bool inCurrentMapLocked(int keyframe_id) const;
  /// The frame's world pose with the snapshot's keyframe poses; false when its keyframe is
  /// unknown.
  static bool composeFrame(const FrameRecord& f, const MapSnapshot& s, StampedPose& out);
  void setKeyframeLocked(const KeyframeRecord& record);
  /// Under the mutex, after a change: publishes the state as the new snapshot (the keyframe
  /// poses copied only when `keyframes_changed`).
  void publishLocked(bool keyframes_changed);

  mutable std::mutex mutex_;
  MapFrames maps_;
  KeyframeTable keyframes_;
  std::vector<int> follows_;               ///< indexed by id: the keyframe it moves with (-1)
  std::vector<bool> culled_;               ///< indexed by id: its data was dropped (cullKeyframe)
  concurrency::AppendOnlyLog<FrameRecord, kFrameChunk> frames_;
  std::size_t frame_history_ = 0;
  /// Held by the frame log's readers and by retireFrames() (which frees records), never by
  /// tracking (the writer); guards the retired frames too.
  mutable std::mutex frames_mutex_;
  std::vector<StampedPose> retired_;
  std::int64_t retired_count_ = 0;
  std::int64_t retired_lost_ = 0;
  std::vector<std::shared_ptr<const MapSnapshot::PointBlock>> points_;
  std::size_t point_count_ = 0;
  std::map<int, std::shared_ptr<const MarginalizedKeyframe>> data_;
  std::size_t data_bytes_ = 0;
  CovisibilityGraph covisibility_;
  SpatialIndex spatial_;
  /// Written under mutex_ (std::atomic_store), read without it (std::atomic_load).
  std::shared_ptr<const MapSnapshot> snapshot_;
};

}  // namespace ldsm
