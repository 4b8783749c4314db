// Similarity transforms between trajectories and their least-squares estimate (Umeyama 1991).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "ldsm/types.h"

namespace ldsm::eval {

/// A similarity transform x -> scale * rotation * x + translation. Used to map an estimated
/// trajectory into the ground-truth frame (est -> gt). A rigid (SE(3)) alignment has scale 1.
struct Alignment {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  double scale = 1.0;

  static Alignment identity() { return {}; }

  /// Maps a point.
  Eigen::Vector3d apply(const Eigen::Vector3d& p) const {
    return scale * (rotation * p) + translation;
  }
  /// Maps a camera-to-world pose: its position is mapped as a point, its orientation is rotated.
  /// (The scale does not act on orientations.)
  Pose apply(const Pose& pose) const;
  /// The inverse transform (scale must be non-zero).
  Alignment inverse() const;
  /// Composition: (a * b).apply(x) == a.apply(b.apply(x)).
  Alignment operator*(const Alignment& other) const;
  /// The rotation angle in radians, in [0, pi].
  double rotationAngle() const;
};

/// Least-squares similarity (with_scale) or rigid transform that maps `est[i]` onto `gt[i]`,
/// minimising sum_i ||gt[i] - (s R est[i] + t)||^2 (Umeyama, PAMI 1991; the rotation is forced to
/// be proper, det R = +1).
/// Throws ldsm::InputError when the sets differ in size, have fewer than 3 points, or are
/// degenerate: all points coincide, or the points of either set are collinear (the rotation about
/// the line would be undetermined).
Alignment alignUmeyama(const std::vector<Eigen::Vector3d>& est,
                       const std::vector<Eigen::Vector3d>& gt, bool with_scale);

}  // namespace ldsm::eval
