// The Lie groups with ceres::Jet scalars: they compile, and autodiff through exp/log/action (also
// at exactly the identity, where the series are used) reproduces the analytic Jacobians.
#include <gtest/gtest.h>

#include "lie_test_utils.h"
#include "math/se3.h"
#include "math/sim3.h"
#include "math/so3.h"

#if __has_include(<ceres/jet.h>)
#include <ceres/jet.h>
#define LDSM_HAVE_CERES_JET 1
#endif

namespace ldsm {
namespace {

#ifdef LDSM_HAVE_CERES_JET

using Eigen::Vector3d;
using test::maxAbsDiff;
using test::TestRandom;

// Jets for d = 0 seeded with the unit directions, and the derivative part of a result.
template <int N>
Eigen::Matrix<ceres::Jet<double, N>, N, 1> seedAtZero() {
  Eigen::Matrix<ceres::Jet<double, N>, N, 1> d;
  for (int i = 0; i < N; ++i) d(i) = ceres::Jet<double, N>(0.0, i);
  return d;
}
template <int N, int M>
Eigen::Matrix<double, M, N> derivative(const Eigen::Matrix<ceres::Jet<double, N>, M, 1>& y) {
  Eigen::Matrix<double, M, N> J;
  for (int i = 0; i < M; ++i) J.row(i) = y(i).v.transpose();
  return J;
}
template <int N, int M>
Eigen::Matrix<double, M, 1> value(const Eigen::Matrix<ceres::Jet<double, N>, M, 1>& y) {
  Eigen::Matrix<double, M, 1> v;
  for (int i = 0; i < M; ++i) v(i) = y(i).a;
  return v;
}

constexpr double kTol = 1e-12;  // autodiff is exact up to rounding

TEST(LieAutodiff, SO3LogOfPerturbedRotation) {
  using J3 = ceres::Jet<double, 3>;
  TestRandom rnd(51);
  for (double angle : {0.0, 1e-9, 0.5, 3.0}) {
    const SO3d R = SO3d::exp(rnd.rotationVector(angle, angle));
    const auto d = seedAtZero<3>();
    const Eigen::Matrix<J3, 3, 1> y = (SO3<J3>::exp(d) * R.cast<J3>()).log();
    EXPECT_LT(maxAbsDiff(value(y), R.log()), kTol);
    EXPECT_LT(maxAbsDiff(derivative(y), SO3d::leftJacobianInverse(R.log())), 1e-11) << angle;
  }
}

TEST(LieAutodiff, SE3ActionAndLog) {
  using J6 = ceres::Jet<double, 6>;
  TestRandom rnd(52);
  for (double angle : {0.0, 1e-9, 0.5, 3.0}) {
    Eigen::Matrix<double, 6, 1> x;
    x << rnd.vector<3>(2.0), rnd.rotationVector(angle, angle);
    const SE3d T = SE3d::exp(x);
    const Vector3d p = rnd.vector<3>(3.0);
    const auto d = seedAtZero<6>();
    const SE3<J6> Tj = T.cast<J6>();
    const Eigen::Matrix<J6, 3, 1> q = (SE3<J6>::exp(d) * Tj) * p.cast<J6>();
    EXPECT_LT(maxAbsDiff(value(q), T * p), kTol);
    EXPECT_LT(maxAbsDiff(derivative(q), T.actionJacobianLeft(p)), kTol) << angle;
    const Eigen::Matrix<J6, 6, 1> y = (Tj * SE3<J6>::exp(d)).log();
    EXPECT_LT(maxAbsDiff(derivative(y), T.logJacobianRight()), 1e-10) << angle;
  }
}

TEST(LieAutodiff, Sim3ActionAndLog) {
  using J7 = ceres::Jet<double, 7>;
  TestRandom rnd(53);
  for (double angle : {0.0, 1e-9, 0.2}) {
    for (double sigma : {0.0, 1e-10, 0.3}) {
      Eigen::Matrix<double, 7, 1> x;
      x << rnd.vector<3>(0.2), rnd.rotationVector(angle, angle), sigma;
      const Sim3d T = Sim3d::exp(x);
      const Vector3d p = rnd.vector<3>(3.0);
      const auto d = seedAtZero<7>();
      const Sim3<J7> Tj = T.cast<J7>();
      const Eigen::Matrix<J7, 3, 1> q = (Sim3<J7>::exp(d) * Tj) * p.cast<J7>();
      EXPECT_LT(maxAbsDiff(value(q), T * p), kTol);
      EXPECT_LT(maxAbsDiff(derivative(q), T.actionJacobianLeft(p)), kTol);
      // The series Jacobian is accurate to ~|ad(x)|^10 / 4.8e7 here.
      const Eigen::Matrix<J7, 7, 1> y = (Tj * Sim3<J7>::exp(d)).log();
      EXPECT_LT(maxAbsDiff(derivative(y), T.logJacobianRight()), 1e-10) << angle << " " << sigma;
    }
  }
}

TEST(LieAutodiff, FloatJetsCompile) {
  using Jf = ceres::Jet<float, 6>;
  Eigen::Matrix<Jf, 6, 1> x;
  for (int i = 0; i < 6; ++i) x(i) = Jf(0.1f * static_cast<float>(i), i);
  const SE3<Jf> T = SE3<Jf>::exp(x);
  EXPECT_NEAR(T.log()(5).a, 0.5f, 1e-6f);
}

#else

TEST(LieAutodiff, SkippedWithoutCeres) {
  GTEST_SKIP() << "ceres/jet.h not available";
}

#endif

}  // namespace
}  // namespace ldsm
