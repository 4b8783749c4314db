// Value types of the public API: poses, stamped poses, trajectories, map points.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace ldsm {

/// A rigid pose as a value: rotation (unit quaternion) and translation. When it describes a camera
/// it is camera-to-world (T_wc), as in the TUM trajectory format.
struct Pose {
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  static Pose identity() { return {}; }
  Eigen::Isometry3d isometry() const {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = rotation.normalized().toRotationMatrix();
    T.translation() = translation;
    return T;
  }
  static Pose fromIsometry(const Eigen::Isometry3d& T) {
    Pose p;
    p.rotation = Eigen::Quaterniond(T.rotation()).normalized();
    p.translation = T.translation();
    return p;
  }
};

/// A pose at a time (seconds).
struct StampedPose {
  double timestamp = 0.0;
  Pose pose;
  /// 0: in the map's frame (the first map's, or a loaded map's). n > 0: the pose belongs to the
  /// n-th map started after tracking was lost for good, not (yet) merged into the map: it is in
  /// that map's own frame and scale.
  int map = 0;
};

using Trajectory = std::vector<StampedPose>;

/// A point of the map in world coordinates with its grey value.
struct MapPoint {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  float intensity = 0.f;
  bool is_corner = false;
  int map = 0;  ///< as StampedPose::map
};

}  // namespace ldsm
