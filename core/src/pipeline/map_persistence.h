// Saved maps in the running engine (docs/map-file.md): what the stages hold of the first map, as
// a MapData value (mapfile/map_data.h), and the stages started again from one. The codec
// (mapfile/map_codec.h) turns the value into the file's bytes.
#pragma once

#include <limits>
#include <string>

#include "camera/pyramid_camera.h"
#include "ldsm/camera/calibration.h"
#include "loop/loop_closer.h"
#include "map/map_store.h"
#include "mapfile/map_data.h"
#include "pipeline/mapping_stage.h"
#include "pipeline/tracking_stage.h"

namespace ldsm {

/// The calibration the engine runs with, as a saved map records it.
MapCalibration mapCalibration(const LevelCamera& camera, const PhotometricCalibration& photometric,
                              double radial_k);

/// What of the map is saved.
struct MapExportScope {
  /// Keyframes with ids from this one on are left out (a loaded map's keyframes have smaller
  /// ids): localising only, the map saved is the map loaded, whatever the run made meanwhile.
  int keyframes_below = std::numeric_limits<int>::max();
  /// The window's keyframes join the map as they would if they left it now.
  bool window = true;
};

/// The first map (with everything merged into it) and, with scope.window, the window's keyframes
/// as the map would keep them, in the frame poses are reported in. The stages must be idle (after
/// finish()).
MapData exportMap(const MapStore& store, MappingStage& mapping, const loop::LoopCloser* loop,
                  const LevelCamera& camera, const MapCalibration& calibration,
                  const MapExportScope& scope = {});

/// Starts the stages from a saved map (before the first frame): the store, loop closure (graph,
/// vocabulary, place recognition), keyframe ids after the map's, and tracking that first looks
/// for the camera in it. Throws InputError naming `where` for a map made with another camera.
void importMap(const MapData& map, const MapCalibration& now, const std::string& where,
               MapStore& store, MappingStage& mapping, loop::LoopCloser* loop,
               TrackingStage& tracking);

}  // namespace ldsm
