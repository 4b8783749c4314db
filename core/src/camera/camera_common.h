// Helpers shared by the camera model implementations (private to core/src/camera).
#pragma once

#include <Eigen/Core>
#include <algorithm>

#include "ldsm/camera/camera_model.h"
#include "math/constants.h"

namespace ldsm::camera_detail {

/// Points closer than this to the image plane (Z) cannot be projected by the perspective models.
inline constexpr double kMinDepth = 1e-9;

/// d(X/Z, Y/Z)/d(X, Y, Z).
inline Eigen::Matrix<double, 2, 3> normalizeJacobian(const Eigen::Vector3d& p) {
  const double iz = 1.0 / p.z();
  Eigen::Matrix<double, 2, 3> J;
  J << iz, 0.0, -p.x() * iz * iz, 0.0, iz, -p.y() * iz * iz;
  return J;
}

/// How far (pixels) outside [0, size - 1] a sample may fall and still count as valid (it is
/// clamped to the border): absorbs rounding in the output intrinsics.
inline constexpr double kEdgeTolerance = 1e-3;

/// Where the ray through normalized pinhole coordinates (x, y) lands in the input image. Returns
/// false when the model cannot project it or it falls outside the image; otherwise `px` is
/// clamped to [0, width - 1] x [0, height - 1].
inline bool sampleInput(const CameraModel& cam, double x, double y, Eigen::Vector2d* px) {
  if (!cam.project(Eigen::Vector3d(x, y, 1.0), px) || !cam.inImage(*px, -kEdgeTolerance))
    return false;
  px->x() = std::clamp(px->x(), 0.0, static_cast<double>(cam.width() - 1));
  px->y() = std::clamp(px->y(), 0.0, static_cast<double>(cam.height() - 1));
  return true;
}

}  // namespace ldsm::camera_detail
