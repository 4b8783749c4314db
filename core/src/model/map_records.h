// The records the map keeps, as values: a keyframe's pose, a frame's pose relative to the
// keyframe it was tracked against, and a point that left the window with its host keyframe.
#pragma once

#include <cstdint>

#include "ldsm/types.h"
#include "math/se3.h"

namespace ldsm {

struct KeyframeRecord {
  int id = 0;
  std::int64_t frame_index = 0;
  double timestamp = 0.0;
  SE3d T_w_c;  ///< camera-to-world
  /// Scale of the keyframe's Sim(3) after a loop correction: frames tracked against it are at
  /// T_w_c * (scale * their relative translation).
  double scale = 1.0;
  /// The map it was made in (map/map_frames.h; 0: the first map).
  int map = 0;
};

struct FrameRecord {
  std::int64_t frame_index = 0;
  double timestamp = 0.0;
  int reference_keyframe = -1;  ///< id of the keyframe the frame was tracked against
  SE3d T_ref_c;                 ///< frame pose relative to that keyframe
};

/// A point that left the window, with the id of the keyframe that hosted it (-1: none); it moves
/// with that keyframe on loop closure. The map keeps one per point for the whole run, so it is
/// stored compactly (28 bytes, where a MapPoint and the host took 48): the world position in
/// float, each coordinate to about 6e-8 of its magnitude (nothing in the odometry reads these
/// positions; the window's and the map keyframes' points are their own).
struct HostedPoint {
  HostedPoint() = default;
  HostedPoint(const MapPoint& p, int host_id)
      : position(p.position.cast<float>()),
        intensity(p.intensity),
        host(host_id),
        map(p.map),
        is_corner(p.is_corner) {}

  /// As the public API reports it (MapPoint::map as stored).
  MapPoint mapPoint() const {
    MapPoint m;
    m.position = position.cast<double>();
    m.intensity = intensity;
    m.is_corner = is_corner;
    m.map = map;
    return m;
  }

  Eigen::Vector3f position = Eigen::Vector3f::Zero();  ///< world
  float intensity = 0.f;
  int host = -1;
  int map = 0;  ///< as MapPoint::map
  bool is_corner = false;
};
static_assert(sizeof(HostedPoint) <= 28, "a map point is kept for the whole run: keep it compact");

}  // namespace ldsm
