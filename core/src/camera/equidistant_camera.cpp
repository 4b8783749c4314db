#include <cmath>

#include "camera/camera_models.h"
#include "camera_common.h"
#include "math/constants.h"

namespace ldsm {
namespace {

/// Relative distance to the optical axis below which the axis limit of the formulas is used.
constexpr double kAxisEps = 1e-10;

}  // namespace

EquidistantCamera::EquidistantCamera(const CameraIntrinsics& intrinsics)
    : CameraModel(intrinsics, CameraModelType::Equidistant), theta_max_(kPi) {
  // theta_d(theta) must increase: find the first angle where its derivative vanishes.
  constexpr int kSteps = 4000;
  double prev = 0.0;
  for (int i = 1; i <= kSteps; ++i) {
    const double theta = kPi * i / kSteps;
    double deriv = 0.0;
    distortTheta(theta, &deriv);
    if (!(deriv > 0.0)) {
      double lo = prev, hi = theta;
      for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (lo + hi);
        distortTheta(mid, &deriv);
        (deriv > 0.0 ? lo : hi) = mid;
      }
      theta_max_ = lo;
      break;
    }
    prev = theta;
  }
}

std::unique_ptr<CameraModel> EquidistantCamera::clone() const {
  return std::make_unique<EquidistantCamera>(*this);
}

double EquidistantCamera::distortTheta(double theta, double* derivative) const {
  const auto& k = intrinsics_.distortion;
  const double t2 = theta * theta;
  const double poly = 1.0 + t2 * (k[0] + t2 * (k[1] + t2 * (k[2] + t2 * k[3])));
  if (derivative != nullptr)
    *derivative = 1.0 + t2 * (3.0 * k[0] + t2 * (5.0 * k[1] + t2 * (7.0 * k[2] + t2 * 9.0 * k[3])));
  return theta * poly;
}

bool EquidistantCamera::project(const Eigen::Vector3d& p, Eigen::Vector2d* px,
                                PointJacobian* J) const {
  const double n2 = p.squaredNorm();
  if (!(n2 > 0.0) || !std::isfinite(n2)) return false;
  const double rho = std::hypot(p.x(), p.y());
  const double theta = std::atan2(rho, p.z());
  if (theta > theta_max_) return false;
  if (rho <= kAxisEps * std::sqrt(n2)) {
    // On the optical axis: theta_d / rho -> 1 / Z, the model is locally a pinhole.
    if (!(p.z() > 0.0)) return false;
    *px = toPixel(p.head<2>() / p.z());
    if (J != nullptr) {
      const Eigen::Matrix<double, 2, 3> dn = camera_detail::normalizeJacobian(p);
      J->row(0) = intrinsics_.fx * dn.row(0);
      J->row(1) = intrinsics_.fy * dn.row(1);
    }
    return true;
  }
  double dfd = 0.0;
  const double fd = distortTheta(theta, &dfd);
  const double s = fd / rho;
  *px = toPixel(s * p.head<2>());
  if (J != nullptr) {
    const Eigen::Vector3d dtheta(p.z() * p.x() / (rho * n2), p.z() * p.y() / (rho * n2), -rho / n2);
    const Eigen::Vector3d drho(p.x() / rho, p.y() / rho, 0.0);
    const Eigen::Vector3d ds = dfd * dtheta / rho - fd / (rho * rho) * drho;
    Eigen::Matrix<double, 2, 3> Jd = p.head<2>() * ds.transpose();
    Jd(0, 0) += s;
    Jd(1, 1) += s;
    J->row(0) = intrinsics_.fx * Jd.row(0);
    J->row(1) = intrinsics_.fy * Jd.row(1);
  }
  return true;
}

bool EquidistantCamera::unproject(const Eigen::Vector2d& px, Eigen::Vector3d* ray) const {
  const Eigen::Vector2d xyd = fromPixel(px);
  if (!xyd.allFinite()) return false;
  const double theta_d = xyd.norm();
  if (theta_d == 0.0) {
    *ray = Eigen::Vector3d::UnitZ();
    return true;
  }
  if (theta_d > distortTheta(theta_max_, nullptr)) return false;
  // Safeguarded Newton on theta_d(theta) = theta_d over [0, theta_max] (monotonic there).
  double lo = 0.0, hi = theta_max_;
  double theta = std::min(theta_d, theta_max_);
  const double tol = 1e-14 * std::max(1.0, theta_d);
  bool converged = false;
  for (int it = 0; it < 200; ++it) {
    double deriv = 0.0;
    const double err = distortTheta(theta, &deriv) - theta_d;
    if (std::abs(err) <= tol) {
      converged = true;
      break;
    }
    (err > 0.0 ? hi : lo) = theta;
    double next = theta - err / deriv;
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (next == theta) {
      converged = std::abs(err) <= 1e-10 * std::max(1.0, theta_d);
      break;
    }
    theta = next;
  }
  if (!converged) return false;
  const double sin_t = std::sin(theta);
  *ray = Eigen::Vector3d(sin_t * xyd.x() / theta_d, sin_t * xyd.y() / theta_d, std::cos(theta));
  return true;
}

bool EquidistantCamera::intrinsicsJacobian(const Eigen::Vector3d& p, IntrinsicsJacobian* J) const {
  const double n2 = p.squaredNorm();
  if (!(n2 > 0.0) || !std::isfinite(n2)) return false;
  const double rho = std::hypot(p.x(), p.y());
  const double theta = std::atan2(rho, p.z());
  if (theta > theta_max_) return false;
  double c = 0.0;  // theta / rho
  if (rho <= kAxisEps * std::sqrt(n2)) {
    if (!(p.z() > 0.0)) return false;
    c = 1.0 / p.z();
  } else {
    c = theta / rho;
  }
  const double poly = theta > 0.0 ? distortTheta(theta, nullptr) / theta : 1.0;
  const Eigen::Vector2d xyd = poly * c * p.head<2>();
  J->setZero(2, 8);
  (*J)(0, 0) = xyd.x();
  (*J)(1, 1) = xyd.y();
  (*J)(0, 2) = 1.0;
  (*J)(1, 3) = 1.0;
  double t_pow = theta * theta;
  for (int i = 0; i < 4; ++i) {
    (*J)(0, 4 + i) = intrinsics_.fx * c * p.x() * t_pow;
    (*J)(1, 4 + i) = intrinsics_.fy * c * p.y() * t_pow;
    t_pow *= theta * theta;
  }
  return true;
}

}  // namespace ldsm
