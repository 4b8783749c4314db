// Everything a saved map holds, as plain values: what relocalisation, map reuse and loop closure
// need to continue in a known place (docs/map-file.md). The System exports it from the map store
// and the loop closer, and builds them again from it; map_codec.h turns it into the versioned,
// checksummed binary file format and back.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "ldsm/camera/calibration.h"
#include "math/sim3.h"
#include "model/map_records.h"
#include "model/marginalized_keyframe.h"

namespace ldsm {

/// The calibration a map was made with. A map only makes sense with the same rectified camera
/// (the loader refuses another image size or pinhole) and the same photometric correction.
struct MapCalibration {
  PinholeIntrinsics camera;  ///< the rectified pinhole the engine works in (level 0)
  double radial_k = 0.0;     ///< residual radial distortion the window applied when it was saved
  /// The online refinement's focal and principal point correction applied when it was saved
  /// (backend/calibration_refinement.h): the map's points were measured in `camera` with fx, fy
  /// times exp(focal_log_scale) and cx, cy shifted by these pixels. A session that loads the map
  /// starts with the same correction.
  double focal_log_scale = 0.0;
  double cx_shift = 0.0;
  double cy_shift = 0.0;
  bool has_response = false;
  bool has_vignette = false;
  /// FNV-1a hash of the inverse response and the vignette (0: neither known); a loaded map made
  /// under another photometric calibration is reported, not silently mixed.
  std::uint64_t photometric_hash = 0;
};

/// A pose-graph edge (loop closure's graph, loop/pose_graph.h): S_from_to ~ S_w_from^-1 S_w_to.
struct MapGraphEdge {
  int from_id = -1;
  int to_id = -1;
  int kind = 0;  ///< loop::PoseGraphEdgeKind as an integer (0 odometry, 1 loop, 2 reuse)
  Sim3d S_from_to;
  Eigen::Matrix<double, 7, 7> information = Eigen::Matrix<double, 7, 7>::Identity();
};

/// A covisibility connection of the map store (map/covisibility_graph.h).
struct MapCovisibility {
  int a = -1;
  int b = -1;
  int weight = 1;
};

struct MapData {
  MapCalibration calibration;
  /// Every keyframe with a pose (kept or culled), by increasing id; KeyframeRecord::map is 0 for
  /// all of them (only the first map, with everything merged into it, is saved).
  std::vector<KeyframeRecord> keyframes;
  /// The keyframes that keep points and features (MarginalizedKeyframe without its image; links
  /// and flags as they were), by increasing id; each id is one of `keyframes`.
  std::vector<MarginalizedKeyframe> data;
  /// The map's points (the cloud of mapPoints()), world coordinates, with their host keyframes.
  std::vector<HostedPoint> points;
  std::vector<MapCovisibility> covisibility;
  std::vector<MapGraphEdge> graph;
  /// The loop closer's vocabulary (loop/vocabulary.h's serialize()); empty when it had none yet.
  std::vector<std::uint8_t> vocabulary;
};

}  // namespace ldsm
