// Residual radial distortion of the rectified images, estimated online from the window.
//
// Model: a ray with pinhole coordinates x = (X/Z, Y/Z) of the output camera appears in the
// rectified image at normalized coordinates x (1 + k |x|^2). The window evaluates its residuals
// with the current k (host pixel -> ray: removeRadial; projection -> target pixel: applyRadial).
// After each window optimisation, radialEnvelopeStep() takes the Newton step in k of the window
// energy with every frame parameter and depth re-optimised (Schur complement of the whole
// Gauss-Newton system, so a direction the poses and depths can absorb, such as the radial flow of
// pure forward motion, carries little weight). RadialRefinement fuses those steps over keyframes
// and decides which correction the window applies.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "camera/radial_distortion.h"
#include "ldsm/config.h"

namespace ldsm {

/// The k row of the window's Gauss-Newton system, beside the frame block and the depths.
struct RadialTerms {
  Eigen::VectorXd H_fk;      ///< sum w J_frames^T J_k (frames x 1)
  std::vector<double> H_dk;  ///< per point: sum w J_d J_k
  double H_kk = 0.0;         ///< sum w J_k^2
  double b_k = 0.0;          ///< sum w J_k r

  void reset(Eigen::Index frame_dim) {
    H_fk.setZero(frame_dim);
    H_dk.clear();
    H_kk = b_k = 0.0;
  }
};

/// The Newton step in k and its curvature with frames and depths eliminated: with the full
/// system [[H, C, h_fk], [C^T, D, h_dk], [., ., H_kk]] and gradient [b, b_d, b_k],
///   step = -(b_k - h^T A^-1 g) / (H_kk - h^T A^-1 h)
/// over the depth-reduced frame block A. False (step and curvature 0) when the curvature is not
/// positive or not finite.
bool radialEnvelopeStep(const Eigen::MatrixXd& H, const Eigen::VectorXd& b,
                        const Eigen::MatrixXd& coupling, const std::vector<double>& H_dd,
                        const std::vector<double>& b_d, const RadialTerms& terms, double* step,
                        double* curvature);

/// Fuses the windows' envelope steps into one estimate of k and keeps the correction the window
/// applies. Each window's measurement applied + step is weighted by its curvature against the
/// older ones' (which keep radial_memory of their weight per window). The correction switches on
/// when |estimate| exceeds radial_dead_band, off again below half of it; while on it follows the
/// estimate, clamped to +-radial_max.
class RadialRefinement {
 public:
  explicit RadialRefinement(const CalibrationRefinementConfig& config) : config_(config) {}

  /// Adds one window's step, taken with applied() in effect.
  void addWindowStep(double step, double curvature);
  /// The correction the window applies (0 while off).
  double applied() const { return applied_; }
  /// The current estimate of k.
  double estimate() const { return estimate_; }
  bool engaged() const { return engaged_; }
  /// Windows fused so far.
  int windows() const { return windows_; }

 private:
  CalibrationRefinementConfig config_;
  double estimate_ = 0.0;
  double weight_ = 0.0;  ///< fused curvature of the older windows
  double applied_ = 0.0;
  bool engaged_ = false;
  int windows_ = 0;
};

}  // namespace ldsm
