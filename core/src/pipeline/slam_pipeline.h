// The engine's stages wired together, in one place:
//
//   frame --> TrackingStage ----------(MappingJob: frame, keyframe, init, reset)--> MappingStage
//              |  ^                                                                   |   |
//              |  +--------(ReferenceExchange: newest keyframe's coarse tracker)------+   |
//              |                                                                          |
//              +--(frame poses)--> MapStore <--(keyframe poses, points; corrections)------+
//                                     ^                                                   |
//              LoopCloser <--(keyframes that left the window, as values)------------------+
//                  +--(corrections, taken by the mapping stage at its safe point)
//
// Every stage reports to one EventSink. Queries read the map store and the mapping stage's
// published snapshot; none waits for the optimiser. Deterministic mode runs the mapping stage and
// loop closure inline on the caller's thread; threaded mode gives each its own thread, through
// the same code.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "camera/pyramid_camera.h"
#include "image/pyramid_pool.h"
#include "ldsm/camera/calibration.h"
#include "ldsm/config.h"
#include "ldsm/system.h"
#include "loop/loop_closer.h"
#include "map/map_store.h"
#include "mapfile/map_data.h"
#include "pipeline/event_sink.h"
#include "pipeline/frame_preprocessor.h"
#include "pipeline/mapping_stage.h"
#include "pipeline/tracking_stage.h"

namespace ldsm {

class SlamPipeline {
 public:
  SlamPipeline(const Config& config, const GeometricCalibration& geometric,
               const PhotometricCalibration& photometric);
  ~SlamPipeline();
  SlamPipeline(const SlamPipeline&) = delete;
  SlamPipeline& operator=(const SlamPipeline&) = delete;

  void setListener(SystemListener* listener) { events_.setListener(listener); }

  /// Where each validated frame goes (TrackingStage::process), on the tracking thread (or the
  /// caller's, deterministic).
  TrackingStage& tracking() { return tracking_; }
  /// End of a run (tracking idle): waits for mapping and loop closure, publishes the window.
  void finish() {
    tracking_.finish();
    mapping_.finish();
  }

  TrackingStatus status() const { return tracking_.status(); }
  const PyramidCamera& camera() const { return camera_; }
  MappingStage& mapping() { return mapping_; }

  // Queries, from any thread; they read published state and never wait for the optimiser.
  Trajectory trajectory() const { return store_.frameTrajectory(); }
  Trajectory keyframeTrajectory() const { return store_.keyframeTrajectory(); }
  Trajectory takeRetiredFrames() { return store_.takeRetiredFrames(); }
  std::vector<MapPoint> mapPoints() const;
  /// Fills the engine's part of the statistics (counts, stage timings, loops, calibration).
  void fillStats(SystemStats& stats) const;

  /// The map as saved (pipeline/map_persistence.h); after finish().
  MapData exportMap();
  /// Starts from a saved map, before the first frame (InputError naming `where` for a map made
  /// with another camera).
  void loadMap(const MapData& map, const std::string& where);

 private:
  FramePreprocessor preprocessor_;
  MapCalibration map_calibration_;  ///< the camera and photometric model a saved map records
  bool localize_only_ = false;      ///< map.localize_only: the map saved is the map loaded
  /// Localising only: the loaded map's keyframes end here, and its calibration (radial_k) stays.
  int loaded_keyframes_end_ = 0;
  MapCalibration loaded_calibration_;  ///< the loaded map's (localise-only saves it unchanged)
  PyramidCamera camera_;
  PyramidPool pyramids_;
  MapStore store_;
  EventSink events_;
  std::unique_ptr<loop::LoopCloser> loop_closer_;
  MappingStage mapping_;
  TrackingStage tracking_;
};

}  // namespace ldsm
