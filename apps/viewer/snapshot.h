// What the browser viewer shows, as one value: the trajectory, the keyframes, the map, loop edges,
// reactivated keyframes, the current image with its tracked points and the live figures. A
// SnapshotSource makes one on request: from a running System (live_source.h) or from the output
// folder of a finished run (run_folder_source.h).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace ldsm::viewer {

/// Floats per pose (x y z qx qy qz qw, camera-to-world) and per point (x y z intensity).
inline constexpr int kPoseStride = 7;
inline constexpr int kPointStride = 4;

/// The figures of the side panel; NaN or -1 where a source does not know one.
struct ViewerFigures {
  std::string source;  ///< dataset, device or output folder
  std::string mode;    ///< "live", "offline", "deterministic" or "finished run"
  std::string status;  ///< tracking status
  double fps = 0.0;    ///< frames tracked per second over the last second
  std::int64_t frames = 0;
  std::int64_t tracked_frames = 0;
  std::int64_t dropped_frames = 0;
  std::int64_t keyframes = 0;
  std::int64_t loops = 0;
  std::int64_t reactivations = 0;
  std::int64_t map_points = 0;
  double latency_mean_ms = 0.0;  ///< submit -> tracked
  double latency_p99_ms = 0.0;
  double ms_per_frame = 0.0;
  double rss_mb = 0.0;    ///< resident memory of the process
  double map_mb = 0.0;    ///< kept keyframes and points
  bool finished = false;  ///< no more updates will come
};

/// The newest tracked image (reduced), with the pixels of the points it was tracked with.
struct ViewerImage {
  std::int64_t frame_index = -1;  ///< -1: none
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;  ///< width * height grey values, rows top to bottom
  std::vector<float> points;         ///< x y pairs, pixels of this image
};

struct ViewerSnapshot {
  std::vector<float> trajectory;  ///< kPoseStride floats per tracked frame
  std::vector<float> keyframes;   ///< kPoseStride floats per keyframe
  std::vector<float> points;      ///< kPointStride floats per map point
  /// Loop-closure edges as keyframe indices (into `keyframes`).
  std::vector<std::array<int, 2>> loops;
  /// Keyframes brought back into the window by map reuse (indices into `keyframes`).
  std::vector<int> reactivated;
  bool has_current = false;                  ///< `current` holds the newest tracked pose
  std::array<float, kPoseStride> current{};  ///< newest tracked pose
  ViewerImage image;
  ViewerFigures figures;
};

/// Makes snapshots for the viewer's publishing thread. snapshot() is called from that one thread;
/// without `with_points` the map points may be left out (they are the largest part).
class SnapshotSource {
 public:
  virtual ~SnapshotSource() = default;
  virtual ViewerSnapshot snapshot(bool with_points) = 0;
};

}  // namespace ldsm::viewer
