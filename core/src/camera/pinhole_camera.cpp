#include "camera/camera_models.h"
#include "camera_common.h"

namespace ldsm {

PinholeCamera::PinholeCamera(const CameraIntrinsics& intrinsics)
    : CameraModel(intrinsics, CameraModelType::Pinhole) {}

std::unique_ptr<CameraModel> PinholeCamera::clone() const {
  return std::make_unique<PinholeCamera>(*this);
}

bool PinholeCamera::project(const Eigen::Vector3d& p, Eigen::Vector2d* px, PointJacobian* J) const {
  if (!(p.z() > camera_detail::kMinDepth)) return false;
  const Eigen::Vector2d xy = p.head<2>() / p.z();
  *px = toPixel(xy);
  if (J != nullptr) {
    const Eigen::Matrix<double, 2, 3> dn = camera_detail::normalizeJacobian(p);
    J->row(0) = intrinsics_.fx * dn.row(0);
    J->row(1) = intrinsics_.fy * dn.row(1);
  }
  return true;
}

bool PinholeCamera::unproject(const Eigen::Vector2d& px, Eigen::Vector3d* ray) const {
  const Eigen::Vector2d xy = fromPixel(px);
  *ray = Eigen::Vector3d(xy.x(), xy.y(), 1.0).normalized();
  return true;
}

bool PinholeCamera::intrinsicsJacobian(const Eigen::Vector3d& p, IntrinsicsJacobian* J) const {
  if (!(p.z() > camera_detail::kMinDepth)) return false;
  const Eigen::Vector2d xy = p.head<2>() / p.z();
  J->setZero(2, 4);
  (*J)(0, 0) = xy.x();
  (*J)(1, 1) = xy.y();
  (*J)(0, 2) = 1.0;
  (*J)(1, 3) = 1.0;
  return true;
}

}  // namespace ldsm
