#include "math/so3.h"

#include <gtest/gtest.h>

#include <cmath>

#include "lie_test_utils.h"

namespace ldsm {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using Eigen::VectorXd;
using test::kJacobianTolerance;
using test::maxAbsDiff;
using test::numericJacobian;
using test::TestRandom;

// Independent ground truth: Eigen's angle-axis to matrix conversion.
Matrix3d rodrigues(const Vector3d& w) {
  const double theta = w.norm();
  if (theta == 0.0) return Matrix3d::Identity();
  return Eigen::AngleAxisd(theta, w / theta).toRotationMatrix();
}

TEST(SO3, ExpMatchesAngleAxisAndLogInvertsIt) {
  TestRandom rnd(11);
  for (int i = 0; i < 200; ++i) {
    const Vector3d w = rnd.rotationVector(0.0, M_PI - 1e-3);
    const SO3d R = SO3d::exp(w);
    EXPECT_LT(maxAbsDiff(R.matrix(), rodrigues(w)), 1e-14);
    EXPECT_LT(maxAbsDiff(R.log(), w), 1e-13) << w.transpose();
    EXPECT_NEAR(R.angle(), w.norm(), 1e-13);
  }
}

TEST(SO3, RoundTripAtSingularAngles) {
  TestRandom rnd(12);
  const double angles[] = {0.0,  1e-12, 1e-10,       1e-6,        1e-3,       0.01 - 1e-9,
                           0.01, 0.02,  M_PI - 1e-3, M_PI - 1e-6, M_PI - 1e-9};
  for (double angle : angles) {
    for (int i = 0; i < 20; ++i) {
      const Vector3d w = rnd.rotationVector(angle, angle);
      const SO3d R = SO3d::exp(w);
      EXPECT_LT(maxAbsDiff(R.matrix(), rodrigues(w)), 2e-15) << angle;
      // Relative accuracy at small angles; near pi the angle comes from atan2 and stays accurate.
      EXPECT_LE(maxAbsDiff(R.log(), w), 2e-15 * angle) << angle;
    }
  }
}

TEST(SO3, LogAtExactlyPiReturnsAVectorOfLengthPi) {
  TestRandom rnd(13);
  for (int i = 0; i < 20; ++i) {
    const Vector3d axis = rnd.rotationVector(1.0, 1.0);
    const SO3d R(Eigen::Quaterniond(0.0, axis.x(), axis.y(), axis.z()));  // exactly pi
    const Vector3d w = R.log();
    EXPECT_NEAR(w.norm(), M_PI, 1e-15);
    EXPECT_LT(maxAbsDiff(SO3d::exp(w).matrix(), R.matrix()), 2e-15);
    // Slightly past pi the quaternion flips sign and the log stays within [0, pi].
    const SO3d past = SO3d::exp(axis * (M_PI + 1e-7));
    EXPECT_LE(past.log().norm(), M_PI);
    EXPECT_LT(maxAbsDiff(SO3d::exp(past.log()).matrix(), past.matrix()), 2e-15);
  }
}

// hat/vee and the Lie bracket of every group: lie_group_laws_test.cpp.
TEST(SO3, HatIsTheCrossProduct) {
  TestRandom rnd(14);
  const Vector3d w = rnd.vector<3>(2.0);
  const Vector3d v = rnd.vector<3>(2.0);
  EXPECT_LT(maxAbsDiff(SO3d::hat(w) * v, w.cross(v)), 1e-15);
  EXPECT_EQ(Matrix3d(SO3d::hat(w).transpose()), Matrix3d(-SO3d::hat(w)));
}

// Composition, inverse, the action and float against double: lie_group_laws_test.cpp.
TEST(SO3, InverseIsTheTransposeAndConstructionNormalises) {
  TestRandom rnd(15);
  for (int i = 0; i < 50; ++i) {
    const SO3d A = SO3d::exp(rnd.rotationVector(0, 3));
    EXPECT_LT(maxAbsDiff(A.inverse().matrix(), A.matrix().transpose()), 1e-15);
    EXPECT_LT(maxAbsDiff(SO3d(A.matrix()).matrix(), A.matrix()), 1e-14);
    // A non-unit quaternion is normalised.
    const SO3d C(Eigen::Quaterniond(A.quaternion().coeffs() * 3.5));
    EXPECT_NEAR(C.quaternion().norm(), 1.0, 1e-15);
    EXPECT_LT(maxAbsDiff(C.matrix(), A.matrix()), 1e-15);
  }
}

class SO3Jacobians : public ::testing::TestWithParam<double> {};

TEST_P(SO3Jacobians, MatchNumericDifferentiation) {
  TestRandom rnd(17);
  const double angle = GetParam();
  for (int i = 0; i < 10; ++i) {
    const Vector3d w = rnd.rotationVector(angle, angle);
    const SO3d R = SO3d::exp(w);
    const Matrix3d Jl = numericJacobian(
        [&](const VectorXd& x) -> VectorXd { return (SO3d::exp(x) * R.inverse()).log(); }, w);
    const Matrix3d Jr = numericJacobian(
        [&](const VectorXd& x) -> VectorXd { return (R.inverse() * SO3d::exp(x)).log(); }, w);
    const Matrix3d Jl_inv = numericJacobian(
        [&](const VectorXd& d) -> VectorXd { return (SO3d::exp(d) * R).log(); }, Vector3d::Zero());
    const Matrix3d Jr_inv = numericJacobian(
        [&](const VectorXd& d) -> VectorXd { return (R * SO3d::exp(d)).log(); }, Vector3d::Zero());
    EXPECT_LT(maxAbsDiff(SO3d::leftJacobian(w), Jl), kJacobianTolerance);
    EXPECT_LT(maxAbsDiff(SO3d::rightJacobian(w), Jr), kJacobianTolerance);
    EXPECT_LT(maxAbsDiff(SO3d::leftJacobianInverse(w), Jl_inv), kJacobianTolerance);
    EXPECT_LT(maxAbsDiff(SO3d::rightJacobianInverse(w), Jr_inv), kJacobianTolerance);
    EXPECT_LT(
        maxAbsDiff(SO3d::leftJacobian(w) * SO3d::leftJacobianInverse(w), Matrix3d::Identity()),
        1e-14);
    EXPECT_LT(
        maxAbsDiff(SO3d::rightJacobian(w) * SO3d::rightJacobianInverse(w), Matrix3d::Identity()),
        1e-14);

    const Vector3d p = rnd.vector<3>(3.0);
    const Eigen::MatrixXd Jal = numericJacobian(
        [&](const VectorXd& d) -> VectorXd { return (SO3d::exp(d) * R) * p; }, Vector3d::Zero());
    const Eigen::MatrixXd Jar = numericJacobian(
        [&](const VectorXd& d) -> VectorXd { return (R * SO3d::exp(d)) * p; }, Vector3d::Zero());
    const Eigen::MatrixXd Jp =
        numericJacobian([&](const VectorXd& q) -> VectorXd { return R * Vector3d(q); }, p);
    EXPECT_LT(maxAbsDiff(R.actionJacobianLeft(p), Jal), kJacobianTolerance);
    EXPECT_LT(maxAbsDiff(SO3d::actionJacobianAtIdentity(R * p), Jal), kJacobianTolerance);
    EXPECT_LT(maxAbsDiff(R.actionJacobianRight(p), Jar), kJacobianTolerance);
    EXPECT_LT(maxAbsDiff(R.actionJacobianPoint(), Jp), kJacobianTolerance);
  }
}

// 0 and 1e-7 exercise the series, 0.01 the switch, 3.0 the neighbourhood of pi.
INSTANTIATE_TEST_SUITE_P(Angles, SO3Jacobians, ::testing::Values(0.0, 1e-7, 0.01, 0.5, 2.0, 3.0));

TEST(SO3, InterpolateFollowsTheGeodesic) {
  TestRandom rnd(19);
  const SO3d R0 = SO3d::exp(rnd.rotationVector(0, 3));
  const Vector3d w = rnd.rotationVector(1.0, 1.0);
  const SO3d R1 = R0 * SO3d::exp(w);
  EXPECT_LT(maxAbsDiff(interpolate(R0, R1, 0.0).matrix(), R0.matrix()), 1e-15);
  EXPECT_LT(maxAbsDiff(interpolate(R0, R1, 1.0).matrix(), R1.matrix()), 1e-14);
  EXPECT_LT(maxAbsDiff(interpolate(R0, R1, 0.25).matrix(), (R0 * SO3d::exp(0.25 * w)).matrix()),
            1e-14);
}

}  // namespace
}  // namespace ldsm
