// Robust camera pose from 3D-2D correspondences (RANSAC over minimal PnP solutions, then a
// least-squares refinement on the inliers): the first step of the geometric loop verification
// and of relocalisation.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "ldsm/camera/calibration.h"
#include "math/se3.h"

namespace ldsm {

/// Settings of solvePnpRansac().
struct PnpRansacSettings {
  int max_iterations = 1000;         ///< RANSAC iterations (adaptive: fewer when inliers abound)
  double inlier_threshold_px = 4.0;  ///< reprojection error of an inlier
  double confidence = 0.999;         ///< probability of drawing one outlier-free sample
  int min_inliers = 20;              ///< fewer inliers: failure
};

/// Result of solvePnpRansac(). `T_camera_points` maps the input 3D points into the camera.
struct PnpRansacResult {
  bool success = false;
  SE3d T_camera_points;
  /// T_camera_points holds the pose RANSAC found: always on success, and also when it found one
  /// with fewer than min_inliers inliers (success false; `inliers` are then that pose's).
  bool has_pose = false;
  std::vector<int> inliers;  ///< indices into the input arrays, increasing
};

/// Finds the pose of a pinhole camera (no distortion) that projects `points` (3D, in their own
/// frame) onto `pixels`. Deterministic (fixed RANSAC seed). Needs at least 6 correspondences;
/// success requires settings.min_inliers inliers. Throws InputError for mismatched sizes, invalid
/// intrinsics or non-finite input.
PnpRansacResult solvePnpRansac(const std::vector<Eigen::Vector3d>& points,
                               const std::vector<Eigen::Vector2d>& pixels,
                               const PinholeIntrinsics& camera, const PnpRansacSettings& settings);

}  // namespace ldsm
