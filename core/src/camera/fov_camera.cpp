#include <cmath>

#include "camera/camera_models.h"
#include "camera_common.h"
#include "math/constants.h"

namespace ldsm {
namespace {

/// Below this omega the closed forms lose precision and their series are used instead.
constexpr double kSmallOmega = 1e-4;

/// atan(a) / a.
double atanRatio(double a) {
  if (std::abs(a) < 1e-4) return 1.0 - a * a / 3.0 + a * a * a * a / 5.0;
  return std::atan(a) / a;
}

/// (d/da [atan(a) / a]) / a.
double atanRatioDerivOverA(double a) {
  const double a2 = a * a;
  if (std::abs(a) < 1e-3) return -2.0 / 3.0 + a2 * (4.0 / 5.0 - a2 * 6.0 / 7.0);
  return (1.0 / (1.0 + a2) - std::atan(a) / a) / a2;
}

}  // namespace

FovCamera::FovCamera(const CameraIntrinsics& intrinsics)
    : CameraModel(intrinsics, CameraModelType::Fov),
      omega_(intrinsics.distortion[0]),
      two_tan_half_omega_(2.0 * std::tan(0.5 * intrinsics.distortion[0])) {}

std::unique_ptr<CameraModel> FovCamera::clone() const {
  return std::make_unique<FovCamera>(*this);
}

bool FovCamera::project(const Eigen::Vector3d& p, Eigen::Vector2d* px, PointJacobian* J) const {
  if (!(p.z() > camera_detail::kMinDepth)) return false;
  const Eigen::Vector2d xy = p.head<2>() / p.z();
  if (!xy.allFinite()) return false;
  const double T = two_tan_half_omega_;
  // c = T / omega -> 1 when omega -> 0 (the model becomes a pinhole).
  const double c = omega_ > kSmallOmega ? T / omega_ : 1.0 + omega_ * omega_ / 12.0;
  const double r = xy.norm();
  const double a = T * r;
  const double g = c * atanRatio(a);  // rd / r
  *px = toPixel(g * xy);
  if (J != nullptr) {
    const double G = c * T * T * atanRatioDerivOverA(a);  // (dg/dr) / r
    Eigen::Matrix2d Jd = G * xy * xy.transpose();
    Jd(0, 0) += g;
    Jd(1, 1) += g;
    const Eigen::Matrix<double, 2, 3> Jn = Jd * camera_detail::normalizeJacobian(p);
    J->row(0) = intrinsics_.fx * Jn.row(0);
    J->row(1) = intrinsics_.fy * Jn.row(1);
  }
  return true;
}

bool FovCamera::unproject(const Eigen::Vector2d& px, Eigen::Vector3d* ray) const {
  const Eigen::Vector2d xyd = fromPixel(px);
  if (!xyd.allFinite()) return false;
  const double rd = xyd.norm();
  double ru_over_rd = 1.0;
  if (omega_ > kSmallOmega) {
    if (!(rd * omega_ < 0.5 * kPi)) return false;  // beyond 90 degrees off-axis
    ru_over_rd = rd > 0.0 ? std::tan(rd * omega_) / (two_tan_half_omega_ * rd)
                          : omega_ / two_tan_half_omega_;
  }
  const Eigen::Vector2d xy = ru_over_rd * xyd;
  if (!xy.allFinite()) return false;
  *ray = Eigen::Vector3d(xy.x(), xy.y(), 1.0).normalized();
  return true;
}

bool FovCamera::intrinsicsJacobian(const Eigen::Vector3d& p, IntrinsicsJacobian* J) const {
  if (!(p.z() > camera_detail::kMinDepth)) return false;
  const Eigen::Vector2d xy = p.head<2>() / p.z();
  if (!xy.allFinite()) return false;
  const double T = two_tan_half_omega_;
  const double r = xy.norm();
  const double a = T * r;
  double g = 0.0, dg_domega = 0.0;
  if (omega_ > kSmallOmega) {
    g = T / omega_ * atanRatio(a);
    dg_domega = ((1.0 + 0.25 * T * T) / (1.0 + a * a) - g) / omega_;
  } else {
    // Series in omega: g = 1 + omega^2 (1/12 - r^2/3) + O(omega^4).
    g = (1.0 + omega_ * omega_ / 12.0) * atanRatio(a);
    dg_domega = omega_ * (1.0 / 6.0 - 2.0 * r * r / 3.0);
  }
  J->setZero(2, 5);
  (*J)(0, 0) = g * xy.x();
  (*J)(1, 1) = g * xy.y();
  (*J)(0, 2) = 1.0;
  (*J)(1, 3) = 1.0;
  (*J)(0, 4) = intrinsics_.fx * dg_domega * xy.x();
  (*J)(1, 4) = intrinsics_.fy * dg_domega * xy.y();
  return true;
}

}  // namespace ldsm
