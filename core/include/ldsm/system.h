// The public face of the engine: construct from a configuration and a calibration, submit frames,
// read back poses, keyframes and the map as values.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "ldsm/camera/calibration.h"
#include "ldsm/config.h"
#include "ldsm/events.h"
#include "ldsm/image.h"
#include "ldsm/types.h"

namespace ldsm {

/// One input frame as a view of the caller's memory (8-bit grey, any stride). The system copies
/// what it needs before submit() returns.
struct FrameView {
  ImageView<const std::uint8_t> image;
  double timestamp = 0.0;                                         ///< seconds, increasing
  double exposure_ms = std::numeric_limits<double>::quiet_NaN();  ///< NaN when unknown
};

/// A point of the map in world coordinates with its grey value.
struct MapPoint {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  float intensity = 0.f;
  bool is_corner = false;
};

/// Timing of one processing stage over the run, milliseconds.
struct StageTiming {
  std::string stage;
  std::int64_t count = 0;
  double mean_ms = 0.0;
  double p50_ms = 0.0;
  double p99_ms = 0.0;
  double max_ms = 0.0;
};

struct SystemStats {
  std::int64_t frames = 0;
  std::int64_t tracked_frames = 0;
  std::int64_t keyframes = 0;
  std::int64_t initializations = 0;  ///< times the map was (re)initialised
  std::int64_t tracking_losses = 0;
  std::int64_t rejected_frames = 0;  ///< frames refused as bad input (size, timestamp, content)
  std::vector<StageTiming> stages;
  std::vector<LoopClosureEvent> loops;  ///< loops closed, in order
};

class System {
 public:
  /// Validates the configuration and the calibration (ConfigError / InputError naming the field).
  System(const Config& config, const GeometricCalibration& geometric,
         const PhotometricCalibration& photometric = {});
  ~System();
  System(const System&) = delete;
  System& operator=(const System&) = delete;

  /// Receives events; may be null. Set before the first submit().
  void setListener(SystemListener* listener);

  /// Processes (deterministic mode) or queues (threaded mode) one frame. A frame of the wrong
  /// size throws InputError; a frame with a NaN/zero exposure, a duplicated or backwards
  /// timestamp, or an all-black/saturated image is rejected with a warning and counted.
  void submit(const FrameView& frame);

  /// Waits until every submitted frame is processed and the last optimisation has finished.
  void finish();

  TrackingStatus status() const;
  /// The final estimate of every processed frame that has a pose (camera-to-world, TUM order).
  Trajectory trajectory() const;
  /// The keyframes' poses (final estimates).
  Trajectory keyframeTrajectory() const;
  /// Every point of the map (active and marginalised), world coordinates.
  std::vector<MapPoint> mapPoints() const;
  SystemStats stats() const;
  /// The ideal pinhole the engine works in (after rectification).
  PinholeIntrinsics rectifiedCamera() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ldsm
