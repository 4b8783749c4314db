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

#include "frontend/pyramid_camera.h"
#include "ldsm/config.h"

namespace ldsm {

/// Image normalized coordinates of the ray with pinhole coordinates (x, y).
inline Eigen::Vector2f applyRadial(float k, float x, float y) {
  const float f = 1.f + k * (x * x + y * y);
  return {x * f, y * f};
}

/// Pinhole coordinates of image normalized coordinates (x, y): applyRadial's inverse. Newton's
/// method on the radial scale t (t (1 + k R^2 t^2) = 1 with R = |(x, y)|), from t = 1; defined
/// while 1 + 3 k r^2 > 0 (for k < 0: inside the radius where the distortion turns back).
inline Eigen::Vector2f removeRadial(float k, float x, float y) {
  const float kr2 = k * (x * x + y * y);
  float t = 1.f;
  for (int it = 0; it < 4; ++it) {
    const float kt2 = kr2 * t * t;
    t -= (t * (1.f + kt2) - 1.f) / (1.f + 3.f * kt2);
  }
  return {x * t, y * t};
}

/// The ray (z = 1) through image pixel (u, v) of `cam` with the radial distortion k.
inline Eigen::Vector3f radialRay(const LevelCamera& cam, float k, float u, float v) {
  const Eigen::Vector2f x = removeRadial(k, cam.fxi * u + cam.cxi, cam.fyi * v + cam.cyi);
  return {x.x(), x.y(), 1.f};
}

/// The image pixel of camera-frame point q (q.z > 0) with the radial distortion k.
inline Eigen::Vector2f radialProject(const LevelCamera& cam, float k, const Eigen::Vector3f& q) {
  const Eigen::Vector2f x = applyRadial(k, q.x() / q.z(), q.y() / q.z());
  return {cam.fx * x.x() + cam.cx, cam.fy * x.y() + cam.cy};
}

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
