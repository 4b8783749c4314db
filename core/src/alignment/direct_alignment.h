// Direct (photometric) alignment of a keyframe's stored points to another image. The points
// (PatchPoint: host pixel, inverse depth, the host's intensities over the residual pattern) are
// projected into the target image, and the pose of the target relative to the host, T_target_host,
// with the affine brightness transfer I_target ~ e^a I_host + b, is found by Levenberg-Marquardt on
// the Huber-weighted photometric error of the patterns, coarse to fine over the target's pyramid
// (at coarser levels the host's level-0 intensities are compared with the smoothed target: good
// enough to pull the pose into the basin of level 0, where the comparison is exact).
//
// This is the measurement the odometry itself makes, with hundreds of points instead of the few
// dozen ORB matches of a feature-based estimate: loop closure refines its Sim(3) constraints with
// it (the feature-based estimate is the start), and relocalisation its PnP poses.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "camera/pyramid_camera.h"
#include "image/image_pyramid.h"
#include "math/se3.h"
#include "model/patch_point.h"

namespace ldsm {

struct DirectAlignmentSettings {
  int coarsest_level = 2;          ///< first pyramid level of the target (clamped to its levels)
  int max_iterations = 30;         ///< Levenberg-Marquardt iterations per level
  float huber_threshold = 9.f;     ///< grey levels
  float outlier_threshold = 30.f;  ///< RMS pattern residual (grey levels) of an outlier point
  float border = 2.f;              ///< pattern pixels closer to the border are out of the image
  /// Weights of the priors (a - a0)^2, (b - b0)^2 towards the initial brightness transfer, per
  /// point in the image (they keep a wrong pose from flattening the contrast).
  double affine_prior_a = 50.0;
  double affine_prior_b = 0.01;
  int min_points = 60;               ///< points that must project into the target at level 0
  double min_inlier_fraction = 0.5;  ///< of those, the share that must be inliers at level 0
  double convergence_step = 1e-6;    ///< stop when the pose step norm falls below this
};

struct DirectAlignmentResult {
  bool success = false;
  std::string failure;  ///< why it failed (empty on success)
  SE3d T_target_host;
  double a = 0.0, b = 0.0;  ///< I_target ~ e^a I_host + b
  /// Information of T_target_host for a left perturbation exp(xi) * T ([rho, phi]): J^T J of the
  /// level-0 inlier residuals, whitened by their a-posteriori variance and divided by the
  /// pattern size (the 8 pixels of a pattern share one depth and most of their errors).
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();
  /// Mean zero-normalised cross-correlation of each level-0 point's pattern with the target's at
  /// its final projection, over the points in the image: near 1 for the right scene, near 0 for
  /// unrelated intensities, whatever contrast and offset the fit chose (and independent of them).
  double pattern_correlation = 0.0;
  int in_image = 0;   ///< level-0 points projecting into the target
  int inliers = 0;    ///< of those, below the outlier threshold
  double rmse = 0.0;  ///< level-0 RMS residual of the inliers (grey levels)
  int iterations = 0;
};

/// Aligns `points` (host pixels and inverse depths in the camera `camera`, level 0) to `target`
/// (a pyramid in the same camera) from the initial pose and brightness transfer. `radial_k` is
/// the residual radial distortion of both images (camera/radial_distortion.h).
DirectAlignmentResult alignPoints(const std::vector<PatchPoint>& points,
                                  const PyramidCamera& camera, float radial_k,
                                  const ImagePyramid& target, const SE3d& T_initial,
                                  double a_initial, double b_initial,
                                  const DirectAlignmentSettings& settings);

}  // namespace ldsm
