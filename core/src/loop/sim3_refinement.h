// Sim(3) refinement of a loop constraint (LDSO eq. 3): given candidate-keyframe 3D points matched
// to current-keyframe features, find S_current_candidate minimising, with Huber norms,
//   3D-3D error  (S p - q) / (|q| sigma_rel)          for matches with depth q in the current KF,
//   2D error     (pi(S p) - u) / sigma_px             for the others (and optionally for all),
// over rotation, translation and scale (scale is free: it comes from the 3D-3D terms). Outliers are
// re-classified between rounds by chi-square tests on the whitened residuals.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "ldsm/camera/calibration.h"
#include "math/sim3.h"

namespace ldsm::loop {

/// One 3D-2D(-3D) correspondence between the candidate and the current keyframe.
struct Sim3Correspondence {
  Eigen::Vector3d point_candidate;  ///< 3D point in the candidate's camera frame (its map scale)
  Eigen::Vector2d pixel_current;    ///< matched feature in the current keyframe
  double idepth_current = 0.0;      ///< inverse depth of that feature (<= 0 or NaN: unknown)
};

/// Settings of refineSim3().
struct Sim3RefinementSettings {
  double pixel_sigma = 1.0;            ///< std. dev. of a 2D feature position [px]
  double depth_relative_sigma = 0.05;  ///< std. dev. of |S p - q| relative to |q|
  double huber_2d = 2.0;               ///< Huber threshold on the whitened 2D residual norm
  double huber_3d = 2.0;               ///< Huber threshold on the whitened 3D residual norm
  double chi2_2d = 5.991;              ///< inlier test of a 2D residual (95 %, 2 DoF)
  double chi2_3d = 7.815;              ///< inlier test of a 3D residual (95 %, 3 DoF)
  /// Add the 2D term to matches with depth too (LDSM's formulation; more accurate rotation when
  /// depths are noisy). false gives LDSO's split exactly.
  bool reprojection_for_depth_matches = true;
  int rounds = 3;           ///< solve / re-classify rounds
  int max_iterations = 15;  ///< Levenberg-Marquardt iterations per round
};

/// Result of refineSim3().
struct Sim3RefinementResult {
  bool success = false;       ///< false: no correspondence in front of the camera, solver error
  Sim3d S_current_candidate;  ///< maps candidate camera points into the current camera
  std::vector<std::uint8_t> inlier;  ///< per input correspondence, after the last round
  int inliers_3d = 0;                ///< inliers with depth in the current keyframe
  int inliers_2d = 0;                ///< inliers without depth
  double rms_reprojection_px = 0.0;  ///< over all inliers
  /// Information (inverse covariance) of the estimate for a left perturbation
  /// S_current_candidate = exp(d) * S_est, d = [rho, phi, sigma]: J^T J of the inliers' whitened
  /// residuals, divided by the a-posteriori variance factor when the residuals are larger than
  /// the settings' sigmas say (never multiplied: a small factor does not make it more certain).
  Eigen::Matrix<double, 7, 7> information = Eigen::Matrix<double, 7, 7>::Zero();
};

/// Refines `initial` (e.g. from PnP plus a depth-ratio scale). The first round uses the
/// correspondences flagged in `initial_inliers` (e.g. the PnP inliers; nullptr: all), each later
/// round the inliers of the previous one; the result classifies all of them. Throws InputError for
/// invalid intrinsics, non-finite input, a flag vector of the wrong size or settings out of range.
Sim3RefinementResult refineSim3(const std::vector<Sim3Correspondence>& correspondences,
                                const PinholeIntrinsics& camera_current, const Sim3d& initial,
                                const Sim3RefinementSettings& settings,
                                const std::vector<std::uint8_t>* initial_inliers = nullptr);

/// How far a measured S_current_candidate (with its information, Sim3RefinementResult) is from
/// the relative pose that the world poses S_w_current, S_w_candidate imply: d^T I d with
/// d = log(S_implied * S_measured^-1), a squared Mahalanobis distance (chi-square, 7 DoF, when
/// the poses are right and the information honest).
double loopDisagreementChi2(const Sim3d& S_w_current, const Sim3d& S_w_candidate,
                            const Sim3d& S_current_candidate,
                            const Eigen::Matrix<double, 7, 7>& information);

/// Whether a correspondence carries a usable current-keyframe depth.
inline bool hasCurrentDepth(const Sim3Correspondence& c) {
  return c.idepth_current > 0.0 && c.idepth_current < 1e12;  // false for NaN
}

}  // namespace ldsm::loop
