#include "math/sim3.h"

#include <gtest/gtest.h>

#include <cmath>
#include <unsupported/Eigen/MatrixFunctions>

#include "lie_test_utils.h"

namespace ldsm {
namespace {

using Eigen::Matrix4d;
using Eigen::Vector3d;
using Eigen::VectorXd;
using test::kJacobianTolerance;
using test::maxAbsDiff;
using test::numericJacobian;
using test::TestRandom;
using Matrix7d = Eigen::Matrix<double, 7, 7>;
using Vector7d = Eigen::Matrix<double, 7, 1>;

Vector7d tangent(const Vector3d& rho, const Vector3d& phi, double sigma) {
  Vector7d x;
  x << rho, phi, sigma;
  return x;
}

Vector7d randomTangent(TestRandom& rnd, double angle, double sigma) {
  return tangent(rnd.vector<3>(2.0), rnd.rotationVector(angle, angle), sigma);
}

// The singular and switching cases of the closed forms: angle 0, tiny, at the series switch,
// large, near pi; log-scale 0, tiny (scale 1 + 1e-10), at the series switch (|sigma| = 1), large.
const double kAngles[] = {0.0, 1e-10, 1e-6, 0.01, 0.0101, 0.5, 2.5, M_PI - 1e-6};
const double kSigmas[] = {0.0, 1e-10, -1e-10, 1e-6, 0.3, -0.999, 1.0, -1.001, 2.5};

TEST(Sim3, ExpMatchesMatrixExponentialAndLogInvertsIt) {
  TestRandom rnd(31);
  for (double angle : kAngles) {
    for (double sigma : kSigmas) {
      for (int i = 0; i < 4; ++i) {
        const Vector7d x = randomTangent(rnd, angle, sigma);
        const Matrix4d expected = Sim3d::hat(x).exp();
        const Sim3d T = Sim3d::exp(x);
        const double scale = std::max(1.0, expected.cwiseAbs().maxCoeff());
        EXPECT_LT(maxAbsDiff(T.matrix(), expected), 1e-13 * scale) << angle << " " << sigma;
        EXPECT_LT(maxAbsDiff(T.log(), x), 1e-13) << angle << " " << sigma;
        EXPECT_DOUBLE_EQ(T.scale(), std::exp(sigma));
      }
    }
  }
}

TEST(Sim3, ScaleNearOneRoundTrips) {
  TestRandom rnd(32);
  for (double ds : {1e-10, -1e-10, 1e-14, 1e-7}) {
    for (double angle : {0.0, 1e-9, 0.5}) {
      const Sim3d T(SO3d::exp(rnd.rotationVector(angle, angle)), rnd.vector<3>(3.0), 1.0 + ds);
      const Vector7d x = T.log();
      // log(s) = ds - ds^2/2 + ..., up to the rounding of 1 + ds itself.
      EXPECT_NEAR(x(6), ds, ds * ds + 2.3e-16);
      EXPECT_DOUBLE_EQ(x(6), T.logScale());
      EXPECT_LT(maxAbsDiff(Sim3d::exp(x).matrix(), T.matrix()), 1e-14) << ds << " " << angle;
      // The rigid part's SE3 log differs from the first six coordinates by O(ds |t|).
      const Eigen::Matrix<double, 6, 1> y = SE3d(T.so3(), T.translation()).log();
      EXPECT_LT(maxAbsDiff(x.head<6>(), y), 10 * std::abs(ds) * T.translation().norm() + 1e-14);
    }
  }
}

TEST(Sim3, LogAtExactlyPi) {
  for (double scale : {1.0, 1.0 + 1e-10, 0.25}) {
    const Sim3d T(Eigen::Quaterniond(0.0, 0.6, 0.0, 0.8), Vector3d(1.0, -2.0, 0.5), scale);
    const Vector7d x = T.log();
    EXPECT_NEAR(x.segment<3>(3).norm(), M_PI, 1e-15);
    EXPECT_LT(maxAbsDiff(Sim3d::exp(x).matrix(), T.matrix()), 1e-14) << scale;
  }
}

TEST(Sim3, LogScaleIsConsistent) {
  TestRandom rnd(33);
  for (int i = 0; i < 50; ++i) {
    const Sim3d A = Sim3d::exp(randomTangent(rnd, rnd.uniform(0, 3), rnd.uniform(-2, 2)));
    const Sim3d B = Sim3d::exp(randomTangent(rnd, rnd.uniform(0, 3), rnd.uniform(-2, 2)));
    EXPECT_NEAR(A.log()(6), std::log(A.scale()), 1e-15);
    EXPECT_DOUBLE_EQ(A.logScale(), std::log(A.scale()));
    EXPECT_NEAR((A * B).logScale(), A.logScale() + B.logScale(), 1e-14);
    EXPECT_NEAR(A.inverse().logScale(), -A.logScale(), 1e-15);
    // The scale of the matrix is the cube root of its determinant.
    EXPECT_NEAR(std::cbrt(A.matrix().topLeftCorner<3, 3>().determinant()), A.scale(),
                1e-13 * A.scale());
  }
}

// Composition, inverse, the action, hat/vee, the Lie bracket and float against double:
// lie_group_laws_test.cpp.
TEST(Sim3, ActionAndConstruction) {
  TestRandom rnd(34);
  for (int i = 0; i < 50; ++i) {
    const Sim3d A = Sim3d::exp(randomTangent(rnd, rnd.uniform(0, 3), rnd.uniform(-1.5, 1.5)));
    const Vector3d p = rnd.vector<3>(5.0);
    EXPECT_LT(maxAbsDiff(A * p, A.scale() * (A.rotationMatrix() * p) + A.translation()), 1e-13);
    EXPECT_LT(maxAbsDiff(Sim3d(A.matrix()).matrix(), A.matrix()), 1e-13);
    EXPECT_LT(
        maxAbsDiff(Sim3d(A.rotationMatrix(), A.translation(), A.scale()).matrix(), A.matrix()),
        1e-13);
    Sim3d C = A;
    C.setScale(2.0);
    EXPECT_EQ(C.scale(), 2.0);
  }
}

TEST(Sim3, EmbeddingOfSE3) {
  TestRandom rnd(35);
  for (int i = 0; i < 20; ++i) {
    Eigen::Matrix<double, 6, 1> y;
    y << rnd.vector<3>(2.0), rnd.rotationVector(0, 3);
    const SE3d T = SE3d::exp(y);
    const Sim3d S(T);
    const Vector3d p = rnd.vector<3>(3.0);
    EXPECT_LT(maxAbsDiff(S * p, T * p), 1e-15);
    EXPECT_LT(maxAbsDiff(S.log(), tangent(y.head<3>(), y.tail<3>(), 0.0)), 1e-13);
    EXPECT_LT(maxAbsDiff(Sim3d::exp(tangent(y.head<3>(), y.tail<3>(), 0.0)).matrix(), T.matrix()),
              1e-14);
  }
}

TEST(Sim3, ActionJacobiansMatchNumericDifferentiation) {
  TestRandom rnd(38);
  for (double angle : kAngles) {
    for (double sigma : {0.0, 1e-10, 0.7}) {
      const Sim3d T = Sim3d::exp(randomTangent(rnd, angle, sigma));
      const Vector3d p = rnd.vector<3>(3.0);
      const Eigen::MatrixXd Jal = numericJacobian(
          [&](const VectorXd& d) -> VectorXd { return (Sim3d::exp(d) * T) * p; }, Vector7d::Zero());
      const Eigen::MatrixXd Jar = numericJacobian(
          [&](const VectorXd& d) -> VectorXd { return (T * Sim3d::exp(d)) * p; }, Vector7d::Zero());
      const Eigen::MatrixXd Jp =
          numericJacobian([&](const VectorXd& q) -> VectorXd { return T * Vector3d(q); }, p);
      EXPECT_LT(maxAbsDiff(T.actionJacobianLeft(p), Jal), kJacobianTolerance);
      EXPECT_LT(maxAbsDiff(Sim3d::actionJacobianAtIdentity(T * p), Jal), kJacobianTolerance);
      EXPECT_LT(maxAbsDiff(T.actionJacobianRight(p), Jar), kJacobianTolerance);
      EXPECT_LT(maxAbsDiff(T.actionJacobianPoint(), Jp), kJacobianTolerance);
    }
  }
}

// The series Jacobians are meant for the small residuals of a converging pose graph. With
// |ad(x)| <= ~0.7 the truncation error (< |ad|^10 / 4.8e7) stays below the numeric tolerance.
TEST(Sim3, LogJacobiansMatchNumericDifferentiation) {
  TestRandom rnd(39);
  for (double angle : {0.0, 1e-7, 0.01, 0.2, 0.4}) {
    for (double sigma : {0.0, 1e-10, -0.2, 0.3}) {
      const Vector7d x = tangent(rnd.vector<3>(0.2), rnd.rotationVector(angle, angle), sigma);
      const Sim3d T = Sim3d::exp(x);
      const Matrix7d Jl_inv =
          numericJacobian([&](const VectorXd& d) -> VectorXd { return (Sim3d::exp(d) * T).log(); },
                          Vector7d::Zero());
      const Matrix7d Jr_inv =
          numericJacobian([&](const VectorXd& d) -> VectorXd { return (T * Sim3d::exp(d)).log(); },
                          Vector7d::Zero());
      EXPECT_LT(maxAbsDiff(Sim3d::leftJacobianInverse(x), Jl_inv), kJacobianTolerance);
      EXPECT_LT(maxAbsDiff(Sim3d::rightJacobianInverse(x), Jr_inv), kJacobianTolerance);
      EXPECT_LT(maxAbsDiff(T.logJacobianLeft(), Jl_inv), kJacobianTolerance);
      EXPECT_LT(maxAbsDiff(T.logJacobianRight(), Jr_inv), kJacobianTolerance);
    }
  }
}

TEST(Sim3, SeriesJacobianAgreesWithExactSE3OneAtScaleOne) {
  TestRandom rnd(40);
  for (int i = 0; i < 20; ++i) {
    Eigen::Matrix<double, 6, 1> y;
    y << rnd.vector<3>(0.3), rnd.rotationVector(0, 0.4);
    const Matrix7d J = Sim3d::rightJacobianInverse(tangent(y.head<3>(), y.tail<3>(), 0.0));
    EXPECT_LT(maxAbsDiff(J.topLeftCorner<6, 6>(), SE3d::rightJacobianInverse(y)), 1e-11);
  }
}

}  // namespace
}  // namespace ldsm
