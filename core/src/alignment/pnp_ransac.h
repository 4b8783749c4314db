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
  /// Draw at most ten times as many samples as find, with `confidence`, an outlier-free sample
  /// when min_inliers of the correspondences are right (pnpSamplesForInliers): 190 for 20 with
  /// min_inliers 15 instead of max_iterations, none when there are fewer correspondences than
  /// min_inliers. A pose with fewer inliers (has_pose without success) may then be missed: for
  /// callers that use successes only (relocalisation, which tries many frames and candidates).
  bool stop_when_hopeless = false;
};

/// The samples of four correspondences (the minimal sample of solvePnpRansac) that find, with
/// probability `confidence`, an outlier-free one among `correspondences` of which `inliers` are
/// right: ceil(log(1 - confidence) / log(1 - ratio^4)), at least 1; 0 when inliers exceed
/// correspondences, or the ratio is 0.
int pnpSamplesForInliers(int correspondences, int inliers, double confidence);

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
