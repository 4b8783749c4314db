#include "ldsm/eval/alignment.h"

#include <Eigen/SVD>
#include <cmath>
#include <string>

#include "ldsm/error.h"

namespace ldsm::eval {

Pose Alignment::apply(const Pose& pose) const {
  Pose out;
  out.rotation = Eigen::Quaterniond(rotation * pose.rotation.normalized().toRotationMatrix());
  out.rotation.normalize();
  out.translation = apply(pose.translation);
  return out;
}

Alignment Alignment::inverse() const {
  Alignment inv;
  inv.rotation = rotation.transpose();
  inv.scale = 1.0 / scale;
  inv.translation = -inv.scale * (inv.rotation * translation);
  return inv;
}

Alignment Alignment::operator*(const Alignment& other) const {
  Alignment out;
  out.rotation = rotation * other.rotation;
  out.scale = scale * other.scale;
  out.translation = scale * (rotation * other.translation) + translation;
  return out;
}

double Alignment::rotationAngle() const {
  const Eigen::Quaterniond q(rotation);
  return 2.0 * std::atan2(q.vec().norm(), std::abs(q.w()));
}

namespace {

// Relative thresholds below which a point set counts as a single point or as a line.
constexpr double kCoincidentTolerance = 1e-12;
constexpr double kCollinearTolerance = 1e-10;

struct Moments {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  double variance = 0.0;  // mean squared distance to the mean
};

Moments moments(const std::vector<Eigen::Vector3d>& points) {
  Moments m;
  for (const auto& p : points) m.mean += p;
  m.mean /= static_cast<double>(points.size());
  for (const auto& p : points) m.variance += (p - m.mean).squaredNorm();
  m.variance /= static_cast<double>(points.size());
  return m;
}

void checkSpread(const Moments& m, const char* which) {
  const double spread = std::sqrt(m.variance);
  if (!(spread > kCoincidentTolerance * (m.mean.norm() + spread)) || !std::isfinite(spread)) {
    throw InputError(std::string("trajectory alignment: all ") + which +
                     " positions coincide (or are not finite); cannot align");
  }
}

// Second singular value of the centred point set relative to the first: ~0 when collinear.
double planarity(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& mean) {
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : points) cov += (p - mean) * (p - mean).transpose();
  const Eigen::Vector3d sv = Eigen::JacobiSVD<Eigen::Matrix3d>(cov).singularValues();
  return sv(0) > 0.0 ? sv(1) / sv(0) : 0.0;
}

}  // namespace

Alignment alignUmeyama(const std::vector<Eigen::Vector3d>& est,
                       const std::vector<Eigen::Vector3d>& gt, bool with_scale) {
  if (est.size() != gt.size()) {
    throw InputError("trajectory alignment: " + std::to_string(est.size()) +
                     " estimated positions but " + std::to_string(gt.size()) +
                     " ground-truth positions");
  }
  if (est.size() < 3) {
    throw InputError("trajectory alignment: needs at least 3 matched positions, got " +
                     std::to_string(est.size()));
  }
  const Moments me = moments(est);
  const Moments mg = moments(gt);
  checkSpread(me, "estimated");
  checkSpread(mg, "ground-truth");
  if (planarity(est, me.mean) < kCollinearTolerance ||
      planarity(gt, mg.mean) < kCollinearTolerance) {
    throw InputError("trajectory alignment: the " + std::to_string(est.size()) +
                     " positions are collinear; the rotation about the line is undetermined");
  }

  // Cross-covariance of the centred sets: Sigma = 1/n sum (g - mu_g)(e - mu_e)^T.
  Eigen::Matrix3d sigma = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < est.size(); ++i) {
    sigma += (gt[i] - mg.mean) * (est[i] - me.mean).transpose();
  }
  sigma /= static_cast<double>(est.size());

  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(sigma, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d d = svd.singularValues();
  if (!(d(1) > kCollinearTolerance * d(0))) {
    throw InputError(
        "trajectory alignment: the cross-covariance of the positions has rank < 2 "
        "(degenerate motion); cannot determine the rotation");
  }
  Eigen::Vector3d sign = Eigen::Vector3d::Ones();
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0.0) sign(2) = -1.0;

  Alignment a;
  a.rotation = svd.matrixU() * sign.asDiagonal() * svd.matrixV().transpose();
  a.scale = with_scale ? d.dot(sign) / me.variance : 1.0;
  a.translation = mg.mean - a.scale * (a.rotation * me.mean);
  return a;
}

}  // namespace ldsm::eval
