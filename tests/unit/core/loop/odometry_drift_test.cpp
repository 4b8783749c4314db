// The odometry drift model of loop closure: edge information, chain covariance and the
// a-posteriori scale a loop's disagreement gives it.
#include "loop/odometry_drift.h"

#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/Cholesky>

namespace ldsm::loop {
namespace {

const Sim3d kStep(SO3d::exp(Eigen::Vector3d(0.0, 0.02, 0.0)), Eigen::Vector3d(0.1, 0.0, 0.0), 1.0);

TEST(OdometryDrift, EdgeInformationFollowsTheStep) {
  const OdometryDriftModel m{1e-3, 2e-3, 0.01};
  const Matrix7d info = m.edgeInformation(kStep);
  EXPECT_NEAR(info(0, 0), 1.0 / std::pow(0.01 * 0.1, 2), 1e-6);
  EXPECT_NEAR(info(4, 4), 1.0 / 1e-6, 1e-3);
  EXPECT_NEAR(info(6, 6), 1.0 / 4e-6, 1e-3);
  EXPECT_TRUE((info - Matrix7d(info.diagonal().asDiagonal())).isZero());
  // A pure rotation keeps a finite translation information (the floor of the step).
  const Matrix7d rot = m.edgeInformation(Sim3d(kStep.so3(), Eigen::Vector3d::Zero(), 1.0));
  EXPECT_TRUE(rot.allFinite());
  EXPECT_NEAR(rot(0, 0), 1.0 / std::pow(0.01 * m.min_step, 2), 1.0);
}

TEST(OdometryDrift, ChainCovarianceGrowsWithStepsPathAndLeverArm) {
  const OdometryDriftModel m{1e-3, 2e-3, 0.01};
  const Sim3d rel(SO3d(), Eigen::Vector3d(2.0, 0.0, 0.0), 1.0);
  const Matrix7d c10 = m.chainCovariance(10, 1.0, rel);
  const Matrix7d c40 = m.chainCovariance(40, 1.0, rel);
  // Random walks: variance proportional to the number of steps.
  EXPECT_NEAR(c40(3, 3) / c10(3, 3), 4.0, 1e-12);
  EXPECT_NEAR(c40(6, 6) / c10(6, 6), 4.0, 1e-12);
  EXPECT_NEAR(c10(3, 3), 10 * 1e-6, 1e-15);
  // Translation: drift of the path plus rotation and scale drift on the 2 m lever arm.
  EXPECT_NEAR(c10(0, 0), 1e-4 + (10 * 1e-6 + 10 * 4e-6) * 4.0, 1e-12);
  EXPECT_GT(m.chainCovariance(10, 5.0, rel)(0, 0), c10(0, 0));
  // Direction of counting does not matter.
  EXPECT_TRUE(m.chainCovariance(-10, 1.0, rel).isApprox(c10));
}

TEST(OdometryDrift, DriftScaleMakesTheDisagreementTypical) {
  Matrix7d loop_cov = Matrix7d::Identity() * 1e-4;
  Matrix7d chain_cov = Matrix7d::Identity() * 1e-4;
  // Within the noise: no inflation.
  Vector7d small = Vector7d::Constant(1e-2);  // chi2 = 7 * 1e-4 / 2e-4 = 3.5
  EXPECT_EQ(driftScaleFor(small, loop_cov, chain_cov), 1.0);
  // 100 times the variance the model expects: lambda brings chi2 back to 7.
  Vector7d big = Vector7d::Constant(0.1);
  const double lambda = driftScaleFor(big, loop_cov, chain_cov);
  EXPECT_GT(lambda, 1.0);
  const Matrix7d sum = loop_cov + lambda * chain_cov;
  EXPECT_NEAR(big.dot(Eigen::LDLT<Matrix7d>(sum).solve(big)), 7.0, 1e-6);
  // With isotropic covariances: 7 * 0.01 / (1e-4 (1 + lambda)) = 7  ->  lambda = 99.
  EXPECT_NEAR(lambda, 99.0, 1e-6);
}

}  // namespace
}  // namespace ldsm::loop
