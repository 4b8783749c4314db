#include "loop/odometry_drift.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>

namespace ldsm::loop {

Matrix7d OdometryDriftModel::edgeInformation(const Sim3d& S_prev_cur) const {
  const double step = std::max(S_prev_cur.translation().norm(), min_step);
  const double sd_t = translation * step;
  Matrix7d info = Matrix7d::Zero();
  info.diagonal().head<3>().setConstant(1.0 / (sd_t * sd_t));
  info.diagonal().segment<3>(3).setConstant(1.0 / (rotation * rotation));
  info(6, 6) = 1.0 / (scale * scale);
  return info;
}

Matrix7d OdometryDriftModel::chainCovariance(int steps, double path_length,
                                             const Sim3d& S_rel) const {
  const double n = std::max(1, std::abs(steps));
  const double var_phi = n * rotation * rotation;
  const double var_s = n * scale * scale;
  const double arm2 = S_rel.translation().squaredNorm();
  const double sd_t = translation * std::max(path_length, min_step);
  Matrix7d cov = Matrix7d::Zero();
  cov.diagonal().head<3>().setConstant(sd_t * sd_t + (var_phi + var_s) * arm2);
  cov.diagonal().segment<3>(3).setConstant(var_phi);
  cov(6, 6) = var_s;
  return cov;
}

double driftScaleFor(const Vector7d& d, const Matrix7d& loop_cov, const Matrix7d& chain_cov) {
  constexpr double kExpected = 7.0;
  auto chi2 = [&](double lambda) {
    const Matrix7d sum = loop_cov + lambda * chain_cov;
    return d.dot(Eigen::LDLT<Matrix7d>(sum).solve(d));
  };
  if (chi2(1.0) <= kExpected) return 1.0;
  // chi2 falls monotonically with lambda: bisect on log(lambda).
  double lo = 0.0, hi = 1.0;
  while (chi2(std::exp(hi)) > kExpected && hi < 60.0) hi *= 2.0;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (chi2(std::exp(mid)) > kExpected ? lo : hi) = mid;
  }
  return std::exp(hi);
}

}  // namespace ldsm::loop
