// Robust camera pose from 3D-2D correspondences (RANSAC over minimal PnP solutions, then a
// least-squares refinement on the inliers, which are counted again against the refined pose and
// kept when that finds more): the first step of the geometric loop verification and of
// relocalisation.
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
  /// A sample budget from min_inliers (pnpRansacSamples): at most ten times the samples that
  /// find, with `confidence`, an outlier-free one if exactly min_inliers of the correspondences
  /// are right (190 instead of max_iterations for 20 with min_inliers 15), none when there are
  /// fewer correspondences than min_inliers. A success is then still found with high probability
  /// but no longer with all of max_iterations' samples (a pose with exactly min_inliers whose
  /// clean samples mostly keep fewer may be missed), and a pose with fewer inliers (has_pose
  /// without success) often is: for callers that use successes only and try again (relocalisation
  /// tries many frames and candidates).
  bool cap_samples_for_min_inliers = false;
};

/// The samples of four correspondences (the minimal sample of solvePnpRansac) that find, with
/// probability `confidence` (in (0, 1); InputError otherwise), an outlier-free one among
/// `correspondences` of which `inliers` are right: ceil(log(1 - confidence) / log(1 - ratio^4)),
/// at least 1 and at most 1e9; 0 when inliers exceed correspondences or either is not positive.
int pnpSamplesForInliers(int correspondences, int inliers, double confidence);

/// The most samples solvePnpRansac draws for `correspondences` with `settings`: max_iterations,
/// or with cap_samples_for_min_inliers ten times pnpSamplesForInliers(correspondences,
/// min_inliers) when that is fewer (0 when there are fewer correspondences than min_inliers).
int pnpRansacSamples(const PnpRansacSettings& settings, int correspondences);

/// Result of solvePnpRansac(). `T_camera_points` maps the input 3D points into the camera.
struct PnpRansacResult {
  bool success = false;
  SE3d T_camera_points;
  /// T_camera_points holds the pose RANSAC found, refined on its inliers: always on success, and
  /// also when it found one with fewer than min_inliers inliers (success false).
  bool has_pose = false;
  /// Indices into the input arrays, increasing: RANSAC's inliers, or the larger set the refined
  /// pose projects within inlier_threshold_px (in front of the camera).
  std::vector<int> inliers;
};

/// Finds the pose of a pinhole camera (no distortion) that projects `points` (3D, in their own
/// frame) onto `pixels`. Deterministic (fixed RANSAC seed). Needs at least 6 correspondences;
/// success requires settings.min_inliers inliers. Throws InputError for mismatched sizes, invalid
/// intrinsics or non-finite input.
PnpRansacResult solvePnpRansac(const std::vector<Eigen::Vector3d>& points,
                               const std::vector<Eigen::Vector2d>& pixels,
                               const PinholeIntrinsics& camera, const PnpRansacSettings& settings);

}  // namespace ldsm
