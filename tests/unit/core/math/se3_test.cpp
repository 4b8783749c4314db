#include "math/se3.h"

#include <gtest/gtest.h>

#include <cmath>
#include <unsupported/Eigen/MatrixFunctions>

#include "lie_test_utils.h"

namespace ldsm {
namespace {

using Eigen::Matrix3d;
using Eigen::Matrix4d;
using Eigen::Vector3d;
using Eigen::VectorXd;
using test::kJacobianTolerance;
using test::maxAbsDiff;
using test::numericJacobian;
using test::TestRandom;
using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

Vector6d tangent(const Vector3d& rho, const Vector3d& phi) {
  Vector6d x;
  x << rho, phi;
  return x;
}

// A random tangent with translation in [-2, 2]^3 and the given rotation angle.
Vector6d randomTangent(TestRandom& rnd, double angle) {
  return tangent(rnd.vector<3>(2.0), rnd.rotationVector(angle, angle));
}

TEST(SE3, ExpMatchesMatrixExponentialAndLogInvertsIt) {
  TestRandom rnd(21);
  const double angles[] = {0.0, 1e-10, 1e-6, 0.01, 0.3, 1.5, 3.0, M_PI - 1e-6};
  for (double angle : angles) {
    for (int i = 0; i < 20; ++i) {
      const Vector6d x = randomTangent(rnd, angle);
      const Matrix4d expected = SE3d::hat(x).exp();
      const SE3d T = SE3d::exp(x);
      EXPECT_LT(maxAbsDiff(T.matrix(), expected), 1e-13) << angle;
      EXPECT_LT(maxAbsDiff(T.log(), x), 1e-13) << angle;
      EXPECT_LT(maxAbsDiff(SE3d::exp(T.log()).matrix(), T.matrix()), 1e-13) << angle;
    }
  }
}

TEST(SE3, LogAtExactlyPi) {
  const SE3d T(Eigen::Quaterniond(0.0, 0.0, 0.0, 1.0), Vector3d(1.0, -2.0, 0.5));
  const Vector6d x = T.log();
  EXPECT_NEAR(x.tail<3>().norm(), M_PI, 1e-15);
  EXPECT_LT(maxAbsDiff(SE3d::exp(x).matrix(), T.matrix()), 1e-14);
}

// Composition, inverse, the action, hat/vee, the Lie bracket and float against double:
// lie_group_laws_test.cpp.
TEST(SE3, ActionConstructionsAndConversions) {
  TestRandom rnd(23);
  for (int i = 0; i < 50; ++i) {
    const SE3d A = SE3d::exp(randomTangent(rnd, rnd.uniform(0, 3)));
    const Vector3d p = rnd.vector<3>(5.0);
    EXPECT_LT(maxAbsDiff(A * p, A.rotationMatrix() * p + A.translation()), 1e-14);
    EXPECT_LT(maxAbsDiff(SE3d(A.matrix()).matrix(), A.matrix()), 1e-14);
    EXPECT_LT(maxAbsDiff(SE3d(A.rotationMatrix(), A.translation()).matrix(), A.matrix()), 1e-14);
    EXPECT_LT(maxAbsDiff(A.matrix3x4(), A.matrix().topRows<3>()), 1e-15);
    // ldsm::Pose round trip and agreement with its isometry.
    const Pose pose = A.toPose();
    EXPECT_LT(maxAbsDiff(pose.isometry().matrix(), A.matrix()), 1e-14);
    EXPECT_LT(maxAbsDiff(SE3d::fromPose(pose).matrix(), A.matrix()), 1e-15);
  }
}

class SE3Jacobians : public ::testing::TestWithParam<double> {};

TEST_P(SE3Jacobians, MatchNumericDifferentiation) {
  TestRandom rnd(25);
  const double angle = GetParam();
  for (int i = 0; i < 10; ++i) {
    const Vector6d x = randomTangent(rnd, angle);
    const SE3d T = SE3d::exp(x);
    const Matrix6d Jl = numericJacobian(
        [&](const VectorXd& y) -> VectorXd { return (SE3d::exp(y) * T.inverse()).log(); }, x);
    const Matrix6d Jr = numericJacobian(
        [&](const VectorXd& y) -> VectorXd { return (T.inverse() * SE3d::exp(y)).log(); }, x);
    const Matrix6d Jl_inv = numericJacobian(
        [&](const VectorXd& d) -> VectorXd { return (SE3d::exp(d) * T).log(); }, Vector6d::Zero());
    const Matrix6d Jr_inv = numericJacobian(
        [&](const VectorXd& d) -> VectorXd { return (T * SE3d::exp(d)).log(); }, Vector6d::Zero());
    EXPECT_LT(maxAbsDiff(SE3d::leftJacobian(x), Jl), kJacobianTolerance);
    EXPECT_LT(maxAbsDiff(SE3d::rightJacobian(x), Jr), kJacobianTolerance);
    EXPECT_LT(maxAbsDiff(SE3d::leftJacobianInverse(x), Jl_inv), kJacobianTolerance);
    EXPECT_LT(maxAbsDiff(SE3d::rightJacobianInverse(x), Jr_inv), kJacobianTolerance);
    EXPECT_LT(maxAbsDiff(T.logJacobianLeft(), Jl_inv), kJacobianTolerance);
    EXPECT_LT(maxAbsDiff(T.logJacobianRight(), Jr_inv), kJacobianTolerance);
    EXPECT_LT(
        maxAbsDiff(SE3d::leftJacobian(x) * SE3d::leftJacobianInverse(x), Matrix6d::Identity()),
        1e-13);

    const Vector3d p = rnd.vector<3>(3.0);
    const Eigen::MatrixXd Jal = numericJacobian(
        [&](const VectorXd& d) -> VectorXd { return (SE3d::exp(d) * T) * p; }, Vector6d::Zero());
    const Eigen::MatrixXd Jar = numericJacobian(
        [&](const VectorXd& d) -> VectorXd { return (T * SE3d::exp(d)) * p; }, Vector6d::Zero());
    const Eigen::MatrixXd Jp =
        numericJacobian([&](const VectorXd& q) -> VectorXd { return T * Vector3d(q); }, p);
    EXPECT_LT(maxAbsDiff(T.actionJacobianLeft(p), Jal), kJacobianTolerance);
    EXPECT_LT(maxAbsDiff(SE3d::actionJacobianAtIdentity(T * p), Jal), kJacobianTolerance);
    EXPECT_LT(maxAbsDiff(T.actionJacobianRight(p), Jar), kJacobianTolerance);
    EXPECT_LT(maxAbsDiff(T.actionJacobianPoint(), Jp), kJacobianTolerance);
  }
}

// 0 and 1e-7 exercise the series, 0.01 the switch, 3.0 the neighbourhood of pi.
INSTANTIATE_TEST_SUITE_P(Angles, SE3Jacobians, ::testing::Values(0.0, 1e-7, 0.01, 0.5, 2.0, 3.0));

TEST(SE3, InterpolateRotatesAlongTheGeodesicAndTranslatesLinearly) {
  TestRandom rnd(27);
  const SE3d T0 = SE3d::exp(randomTangent(rnd, 1.0));
  const SE3d T1 = SE3d::exp(randomTangent(rnd, 2.0));
  EXPECT_LT(maxAbsDiff(interpolate(T0, T1, 0.0).matrix(), T0.matrix()), 1e-15);
  EXPECT_LT(maxAbsDiff(interpolate(T0, T1, 1.0).matrix(), T1.matrix()), 1e-14);
  const SE3d mid = interpolate(T0, T1, 0.5);
  EXPECT_LT(maxAbsDiff(mid.translation(), 0.5 * (T0.translation() + T1.translation())), 1e-15);
  const double half = (T0.so3().inverse() * mid.so3()).angle();
  EXPECT_NEAR(half, 0.5 * (T0.so3().inverse() * T1.so3()).angle(), 1e-14);
  EXPECT_NEAR((mid.so3().inverse() * T1.so3()).angle(), half, 1e-14);

  // The screw interpolation applied twice from T0 reaches T1.
  const SE3d g = interpolateGeodesic(T0, T1, 0.5);
  const SE3d step = T0.inverse() * g;
  EXPECT_LT(maxAbsDiff((T0 * step * step).matrix(), T1.matrix()), 1e-13);
  EXPECT_LT(maxAbsDiff(interpolateGeodesic(T0, T1, 1.0).matrix(), T1.matrix()), 1e-13);
}

}  // namespace
}  // namespace ldsm
