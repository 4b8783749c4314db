#include <Eigen/LU>
#include <cmath>
#include <limits>

#include "camera/camera_models.h"
#include "camera_common.h"

namespace ldsm {
namespace {

/// Smallest r^2 > 0 where d/dr [r (1 + k1 r^2 + k2 r^4)] = 1 + 3 k1 r^2 + 5 k2 r^4 vanishes.
double radialLimit(double k1, double k2) {
  const double inf = std::numeric_limits<double>::infinity();
  const double a = 5.0 * k2, b = 3.0 * k1;
  if (a == 0.0) return b < 0.0 ? -1.0 / b : inf;
  const double disc = b * b - 4.0 * a;
  if (disc < 0.0) return inf;
  const double sq = std::sqrt(disc);
  double best = inf;
  for (const double s : {(-b - sq) / (2.0 * a), (-b + sq) / (2.0 * a)})
    if (s > 0.0 && s < best) best = s;
  return best;
}

}  // namespace

RadTanCamera::RadTanCamera(const CameraIntrinsics& intrinsics)
    : CameraModel(intrinsics, CameraModelType::RadTan),
      r2_max_(radialLimit(intrinsics.distortion[0], intrinsics.distortion[1])) {}

std::unique_ptr<CameraModel> RadTanCamera::clone() const {
  return std::make_unique<RadTanCamera>(*this);
}

Eigen::Vector2d RadTanCamera::distort(const Eigen::Vector2d& xy, Eigen::Matrix2d* J) const {
  const auto& d = intrinsics_.distortion;
  const double k1 = d[0], k2 = d[1], p1 = d[2], p2 = d[3];
  const double x = xy.x(), y = xy.y();
  const double x2 = x * x, y2 = y * y, xy2 = 2.0 * x * y, r2 = x2 + y2;
  const double radial = 1.0 + r2 * (k1 + k2 * r2);
  const Eigen::Vector2d out(x * radial + p1 * xy2 + p2 * (r2 + 2.0 * x2),
                            y * radial + p1 * (r2 + 2.0 * y2) + p2 * xy2);
  if (J != nullptr) {
    const double dr = 2.0 * (k1 + 2.0 * k2 * r2);  // d(radial)/d(r2) * 2
    const double cross = xy2 * (k1 + 2.0 * k2 * r2) + 2.0 * p1 * x + 2.0 * p2 * y;
    (*J)(0, 0) = radial + x2 * dr + 2.0 * p1 * y + 6.0 * p2 * x;
    (*J)(0, 1) = cross;
    (*J)(1, 0) = cross;
    (*J)(1, 1) = radial + y2 * dr + 6.0 * p1 * y + 2.0 * p2 * x;
  }
  return out;
}

bool RadTanCamera::project(const Eigen::Vector3d& p, Eigen::Vector2d* px, PointJacobian* J) const {
  if (!(p.z() > camera_detail::kMinDepth)) return false;
  const Eigen::Vector2d xy = p.head<2>() / p.z();
  if (!(xy.squaredNorm() <= r2_max_)) return false;
  Eigen::Matrix2d Jd;
  const Eigen::Vector2d xyd = distort(xy, J != nullptr ? &Jd : nullptr);
  *px = toPixel(xyd);
  if (J != nullptr) {
    const Eigen::Matrix<double, 2, 3> Jn = Jd * camera_detail::normalizeJacobian(p);
    J->row(0) = intrinsics_.fx * Jn.row(0);
    J->row(1) = intrinsics_.fy * Jn.row(1);
  }
  return true;
}

bool RadTanCamera::unproject(const Eigen::Vector2d& px, Eigen::Vector3d* ray) const {
  const Eigen::Vector2d target = fromPixel(px);
  if (!target.allFinite()) return false;
  const double tol = 1e-13 * std::max(1.0, target.norm());
  Eigen::Vector2d xy = target;
  Eigen::Matrix2d J;
  Eigen::Vector2d residual = distort(xy, &J) - target;
  for (int it = 0; it < 100 && residual.norm() > tol; ++it) {
    const double det = J.determinant();
    if (!(std::abs(det) > 1e-12)) return false;
    Eigen::Vector2d step = J.inverse() * residual;
    // Damp steps that would leave the invertible domain.
    Eigen::Vector2d next = xy - step;
    for (int halvings = 0; !(next.squaredNorm() <= r2_max_) && halvings < 60; ++halvings) {
      step *= 0.5;
      next = xy - step;
    }
    xy = next;
    residual = distort(xy, &J) - target;
  }
  if (!(residual.norm() <= 1e-9 * std::max(1.0, target.norm())) || !(xy.squaredNorm() <= r2_max_))
    return false;
  *ray = Eigen::Vector3d(xy.x(), xy.y(), 1.0).normalized();
  return true;
}

bool RadTanCamera::intrinsicsJacobian(const Eigen::Vector3d& p, IntrinsicsJacobian* J) const {
  if (!(p.z() > camera_detail::kMinDepth)) return false;
  const Eigen::Vector2d xy = p.head<2>() / p.z();
  if (!(xy.squaredNorm() <= r2_max_)) return false;
  const Eigen::Vector2d xyd = distort(xy, nullptr);
  const double x = xy.x(), y = xy.y(), r2 = x * x + y * y;
  const double fx = intrinsics_.fx, fy = intrinsics_.fy;
  J->setZero(2, 8);
  (*J)(0, 0) = xyd.x();
  (*J)(1, 1) = xyd.y();
  (*J)(0, 2) = 1.0;
  (*J)(1, 3) = 1.0;
  (*J)(0, 4) = fx * x * r2;
  (*J)(1, 4) = fy * y * r2;
  (*J)(0, 5) = fx * x * r2 * r2;
  (*J)(1, 5) = fy * y * r2 * r2;
  (*J)(0, 6) = fx * 2.0 * x * y;
  (*J)(1, 6) = fy * (r2 + 2.0 * y * y);
  (*J)(0, 7) = fx * (r2 + 2.0 * x * x);
  (*J)(1, 7) = fy * 2.0 * x * y;
  return true;
}

}  // namespace ldsm
