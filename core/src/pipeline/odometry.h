// The odometry pipeline for one frame at a time: preprocessing, initialisation, tracking,
// keyframe decisions and mapping, in order. The System runs it directly (deterministic mode) or
// splits it over threads.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "backend/mapper.h"
#include "frontend/coarse_initializer.h"
#include "frontend/frame_tracker.h"
#include "ldsm/events.h"
#include "ldsm/system.h"
#include "map/map_store.h"
#include "pipeline/frame_preprocessor.h"
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
  std::vector<StageTiming> timings() const { return timer_.summary(); }
  std::int64_t keyframes() const { return keyframes_; }
  std::int64_t initializations() const { return initializations_; }
  std::int64_t losses() const { return losses_; }
  /// Publishes the current window poses to the map store (end of a run).
  void flush();

 private:
  OdometryStep initializeStep(std::unique_ptr<ImagePyramid> pyr, std::int64_t index,
                              double timestamp, double exposure);
  OdometryStep trackStep(std::unique_ptr<ImagePyramid> pyr, std::int64_t index, double timestamp,
                         double exposure);
  void loseTracking(OdometryStep& step, const std::string& reason);
  void updateTrackerReference();

  Config config_;
  FramePreprocessor preprocessor_;
  PyramidCamera camera_;
  MapStore store_;
  Mapper mapper_;
  CoarseInitializer initializer_;
  FrameTracker tracker_;
  StageTimer timer_;
  TrackingStatus status_ = TrackingStatus::Initializing;

  std::unique_ptr<ImagePyramid> init_reference_;  ///< the initializer's reference frame
  MapperFrame init_reference_info_;
  SE3d world_anchor_;  ///< world -> camera pose given to a new map's first keyframe
  std::vector<DepthPoint> depth_points_;
  std::int64_t keyframes_ = 0;
  std::int64_t initializations_ = 0;
  std::int64_t losses_ = 0;
};

}  // namespace ldsm
