// Helpers for the Lie-group tests: seeded random elements and central numeric differentiation.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <functional>
#include <random>

namespace ldsm::test {

/// Tolerance for analytic Jacobians against central differences with step kNumericStep: the
/// truncation error is ~h^2 |f'''| ~ 1e-12 and the rounding error ~eps |f| / h ~ 1e-10.
inline constexpr double kNumericStep = 1e-6;
inline constexpr double kJacobianTolerance = 1e-7;

/// Factor on the float-vs-double tolerances: Eigen's ARMv7 NEON float division and square root
/// are refined reciprocal estimates (measured up to ~2e-5 off in 4x4 matrices, against ~1e-7
/// for IEEE float elsewhere).
#if defined(__arm__) && !defined(__aarch64__) && defined(__ARM_NEON)
inline constexpr double kFloatSlack = 20.0;
#else
inline constexpr double kFloatSlack = 1.0;
#endif

/// J(i, j) = (f(x + h e_j) - f(x - h e_j))_i / 2h.
inline Eigen::MatrixXd numericJacobian(
    const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f, const Eigen::VectorXd& x,
    double h = kNumericStep) {
  const Eigen::VectorXd f0 = f(x);
  Eigen::MatrixXd J(f0.size(), x.size());
  for (Eigen::Index j = 0; j < x.size(); ++j) {
    Eigen::VectorXd xp = x;
    Eigen::VectorXd xm = x;
    xp(j) += h;
    xm(j) -= h;
    J.col(j) = (f(xp) - f(xm)) / (2 * h);
  }
  return J;
}

/// Largest absolute difference of two equally sized matrices.
template <typename A, typename B>
double maxAbsDiff(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b) {
  EXPECT_EQ(a.rows(), b.rows());
  EXPECT_EQ(a.cols(), b.cols());
  return (a.template cast<double>() - b.template cast<double>()).cwiseAbs().maxCoeff();
}

/// Deterministic random numbers for the tests.
class TestRandom {
 public:
  explicit TestRandom(unsigned seed) : rng_(seed) {}
  double uniform(double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng_);
  }
  /// A vector with components uniform in [-a, a].
  template <int N>
  Eigen::Matrix<double, N, 1> vector(double a) {
    Eigen::Matrix<double, N, 1> v;
    for (int i = 0; i < N; ++i) v(i) = uniform(-a, a);
    return v;
  }
  /// A rotation vector with a uniform random axis and angle in [lo, hi].
  Eigen::Vector3d rotationVector(double lo, double hi) {
    Eigen::Vector3d axis;
    do {
      axis = vector<3>(1.0);
    } while (axis.norm() < 0.1 || axis.norm() > 1.0);
    return axis.normalized() * uniform(lo, hi);
  }

 private:
  std::mt19937 rng_;
};

}  // namespace ldsm::test
