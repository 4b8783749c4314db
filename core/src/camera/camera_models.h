// The concrete camera models. Usually built through makeCameraModel() (camera_model.h).
#pragma once

#include "ldsm/camera/camera_model.h"

namespace ldsm {

/// Ideal pinhole: u = fx X/Z + cx, v = fy Y/Z + cy. Valid for Z > 0.
class PinholeCamera final : public CameraModel {
 public:
  explicit PinholeCamera(const CameraIntrinsics& intrinsics);
  std::unique_ptr<CameraModel> clone() const override;
  bool project(const Eigen::Vector3d& p_cam, Eigen::Vector2d* px,
               PointJacobian* J = nullptr) const override;
  bool unproject(const Eigen::Vector2d& px, Eigen::Vector3d* ray) const override;
  bool intrinsicsJacobian(const Eigen::Vector3d& p_cam, IntrinsicsJacobian* J) const override;
};

/// Radial-tangential distortion (OpenCV convention, k1 k2 p1 p2) on x = X/Z, y = Y/Z:
///   xd = x (1 + k1 r^2 + k2 r^4) + 2 p1 x y + p2 (r^2 + 2 x^2)
///   yd = y (1 + k1 r^2 + k2 r^4) + p1 (r^2 + 2 y^2) + 2 p2 x y.
/// Valid for Z > 0 and radii where the radial distortion is still increasing.
/// unproject() inverts it with Newton's method and checks convergence.
class RadTanCamera final : public CameraModel {
 public:
  explicit RadTanCamera(const CameraIntrinsics& intrinsics);
  std::unique_ptr<CameraModel> clone() const override;
  bool project(const Eigen::Vector3d& p_cam, Eigen::Vector2d* px,
               PointJacobian* J = nullptr) const override;
  bool unproject(const Eigen::Vector2d& px, Eigen::Vector3d* ray) const override;
  bool intrinsicsJacobian(const Eigen::Vector3d& p_cam, IntrinsicsJacobian* J) const override;

  /// Largest valid r^2 = x^2 + y^2 (infinity when the radial distortion is monotonic).
  double maxRadiusSquared() const { return r2_max_; }

 private:
  /// Distorts normalized coordinates; `J` receives d(distorted)/d(undistorted).
  Eigen::Vector2d distort(const Eigen::Vector2d& xy, Eigen::Matrix2d* J) const;

  double r2_max_;
};

/// Equidistant / Kannala-Brandt fisheye (OpenCV fisheye convention, k1..k4). With theta the angle
/// between the ray and the optical axis, theta_d = theta (1 + k1 t^2 + k2 t^4 + k3 t^6 + k4 t^8),
/// xd = theta_d X / sqrt(X^2 + Y^2) (same for y). Valid for theta below the angle where theta_d
/// stops increasing (which may exceed 90 degrees: points with Z <= 0 can be visible).
class EquidistantCamera final : public CameraModel {
 public:
  explicit EquidistantCamera(const CameraIntrinsics& intrinsics);
  std::unique_ptr<CameraModel> clone() const override;
  bool project(const Eigen::Vector3d& p_cam, Eigen::Vector2d* px,
               PointJacobian* J = nullptr) const override;
  bool unproject(const Eigen::Vector2d& px, Eigen::Vector3d* ray) const override;
  bool intrinsicsJacobian(const Eigen::Vector3d& p_cam, IntrinsicsJacobian* J) const override;

  /// Largest valid angle from the optical axis, radians.
  double maxTheta() const { return theta_max_; }

 private:
  double distortTheta(double theta, double* derivative) const;

  double theta_max_;
};

/// FOV / ATAN model of Devernay and Faugeras as used by PTAM and TUM-Mono (parameter omega): with
/// r = |(X/Z, Y/Z)|, the distorted radius is rd = atan(2 r tan(omega / 2)) / omega. omega = 0 is
/// the pinhole. Valid for Z > 0.
class FovCamera final : public CameraModel {
 public:
  explicit FovCamera(const CameraIntrinsics& intrinsics);
  std::unique_ptr<CameraModel> clone() const override;
  bool project(const Eigen::Vector3d& p_cam, Eigen::Vector2d* px,
               PointJacobian* J = nullptr) const override;
  bool unproject(const Eigen::Vector2d& px, Eigen::Vector3d* ray) const override;
  bool intrinsicsJacobian(const Eigen::Vector3d& p_cam, IntrinsicsJacobian* J) const override;

 private:
  double omega_;
  double two_tan_half_omega_;  ///< 2 tan(omega / 2)
};

}  // namespace ldsm
