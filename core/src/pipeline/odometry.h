// The odometry pipeline for one frame at a time: preprocessing, initialisation, tracking,
// keyframe decisions and mapping. In deterministic mode everything runs in order on the caller's
// thread. In threaded mode (startMappingThread) the caller's thread tracks and a mapping thread
// traces, inserts keyframes and optimises the window; tracked frames go to it through a
// lock-free ring, and each new keyframe comes back as a coarse tracker prepared on the mapping
// thread, which the tracking thread swaps in before its next frame.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "backend/mapper.h"
#include "frontend/frame_tracker.h"
#include "frontend/initializer_hypotheses.h"
#include "ldsm/events.h"
#include "ldsm/system.h"
#include "loop/loop_closer.h"
#include "map/map_store.h"
#include "pipeline/frame_preprocessor.h"
#include "pipeline/spsc_ring.h"
#include "pipeline/stage_timer.h"

namespace ldsm {

/// What processing one frame produced.
struct OdometryStep {
  FrameEvent frame;
  std::optional<KeyframeEvent> keyframe;
  std::optional<InitializedEvent> initialized;
  std::optional<TrackingLostEvent> lost;
};

class Odometry {
 public:
  enum Stage { kPreprocess, kInitialize, kTrack, kTrace, kMapping, kTotal, kStageCount };

  Odometry(const Config& config, const GeometricCalibration& geometric,
           const PhotometricCalibration& photometric);
  ~Odometry();

  /// Processes one validated frame. `exposure` is the exposure time to use (1 when unknown).
  OdometryStep process(ImageView<const std::uint8_t> image, std::int64_t index, double timestamp,
                       double exposure);

  TrackingStatus status() const { return status_; }
  const MapStore& store() const { return store_; }
  const PyramidCamera& camera() const { return camera_; }
  std::vector<MapPoint> mapPoints() const;
  /// The radial correction of the calibration: the estimate and what the window applies.
  Eigen::Vector2d radialCorrection() const;
  /// Per-stage timing; in threaded mode trace and mapping are measured on the mapping thread.
  std::vector<StageTiming> timings() const;
  std::int64_t keyframes() const { return keyframes_.load(std::memory_order_relaxed); }
  std::int64_t initializations() const { return initializations_; }
  std::int64_t losses() const { return losses_; }
  /// Publishes the current window poses to the map store (end of a run).
  void flush();

  /// Threaded mode: starts the mapping thread (before the first frame). Keyframe events are then
  /// reported through `on_keyframe`, on the mapping thread; it must not call back into the
  /// System.
  void startMappingThread(std::function<void(const KeyframeEvent&)> on_keyframe);
  /// Waits until the mapping thread has integrated every frame handed to it.
  void waitForMapping();
  /// Frames waiting for the mapping thread (a snapshot).
  std::size_t mappingBacklog() const;
  /// The mapping thread (after startMappingThread), e.g. to pin it to a CPU.
  std::thread::native_handle_type mappingThreadHandle() { return mapping_thread_.native_handle(); }

  /// Loop closures are reported through `on_loop` (on the thread that applies them).
  void setLoopHandler(std::function<void(const LoopClosureEvent&)> on_loop) {
    on_loop_ = std::move(on_loop);
  }
  /// End of a run: waits for the loop task and applies what it found (mapping thread idle).
  void finishLoops();
  std::vector<LoopClosureEvent> loops() const;

 private:
  OdometryStep initializeStep(std::unique_ptr<ImagePyramid> pyr, std::int64_t index,
                              double timestamp, double exposure);
  OdometryStep trackStep(std::unique_ptr<ImagePyramid> pyr, std::int64_t index, double timestamp,
                         double exposure);
  void loseTracking(OdometryStep& step, const std::string& reason);
  void updateTrackerReference();
  /// Applies the loop task's corrections to the map store (mapper's safe point).
  void applyLoopCorrections();

  // Threaded mode (odometry_mapping_thread.cpp).
  struct MappingJob {
    std::unique_ptr<ImagePyramid> pyramid;
    MapperFrame info;
    bool keyframe = false;
  };
  bool threaded() const { return mapping_ring_ != nullptr; }
  void handOverToMapping(std::unique_ptr<ImagePyramid> pyramid, const MapperFrame& info,
                         bool keyframe);
  void mappingLoop();
  void mapJob(MappingJob& job);
  void publishReference();
  void adoptPreparedReference();
  void stopMappingThread();

  Config config_;
  FramePreprocessor preprocessor_;
  PyramidCamera camera_;
  MapStore store_;
  Mapper mapper_;
  InitializerHypotheses initializer_;
  FrameTracker tracker_;
  StageTimer timer_;
  TrackingStatus status_ = TrackingStatus::Initializing;

  std::unique_ptr<ImagePyramid> init_reference_;  ///< the initializer's reference frame
  MapperFrame init_reference_info_;
  SE3d world_anchor_;  ///< world -> camera pose given to a new map's first keyframe
  std::vector<DepthPoint> depth_points_;
  std::unique_ptr<loop::LoopCloser> loop_closer_;
  std::function<void(const LoopClosureEvent&)> on_loop_;
  mutable std::mutex loops_mutex_;
  std::vector<LoopClosureEvent> loops_;
  std::atomic<std::int64_t> keyframes_{0};
  std::int64_t last_tracked_index_ = -1;

  // Threaded mode. The mapper is used by the mapping thread, and by the tracking thread only
  // while the mapping thread is idle (initialisation, reset); mapper_mutex_ also guards it
  // against queries (flush, mapPoints).
  mutable std::mutex mapper_mutex_;
  std::unique_ptr<pipeline::SpscRing<MappingJob>> mapping_ring_;
  std::thread mapping_thread_;
  std::atomic<bool> mapping_stop_{false};
  std::atomic<std::int64_t> jobs_pushed_{0};
  std::atomic<std::int64_t> jobs_done_{0};
  std::atomic<bool> keyframe_in_flight_{false};
  std::function<void(const KeyframeEvent&)> on_keyframe_;
  StageTimer mapping_timer_;
  std::vector<DepthPoint> mapping_depth_points_;
  // The coarse tracker prepared for the newest keyframe, and a spare one (reference_mutex_).
  std::mutex reference_mutex_;
  std::atomic<bool> has_pending_reference_{false};
  std::unique_ptr<CoarseTracker> pending_reference_;
  std::unique_ptr<CoarseTracker> spare_reference_;
  int pending_id_ = -1;
  SE3d pending_T_c_w_;
  std::int64_t pending_frame_index_ = -1;
  std::int64_t initializations_ = 0;
  std::int64_t losses_ = 0;
};

}  // namespace ldsm
