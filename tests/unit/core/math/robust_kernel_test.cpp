#include "math/robust_kernel.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "ldsm/error.h"

namespace ldsm {
namespace {

const double kThreshold = 1.5;
// Residuals on both sides of the threshold, avoiding the kinks at +-k themselves.
const std::vector<double> kResiduals = {-40.0, -3.0, -1.6, -1.4, -0.7, -1e-3, 0.0,
                                        1e-3,  0.5,  1.3,  1.7,  2.9,  10.0};

// cost'(r) by central differences (h = 1e-6: truncation ~1e-12 on these smooth pieces).
template <typename Kernel>
double numericDerivative(const Kernel& k, double r) {
  const double h = 1e-6;
  return (k.cost(r + h) - k.cost(r - h)) / (2 * h);
}

template <typename Kernel>
void expectConsistent(const Kernel& kernel) {
  for (double r : kResiduals) {
    const double d = numericDerivative(kernel, r);
    // Rounding of the difference quotient: ~eps |cost| / h.
    const double tol = 1e-8 * (1.0 + kernel.cost(r));
    EXPECT_NEAR(kernel.derivative(r), d, tol) << r;
    if (r != 0.0) {
      EXPECT_NEAR(kernel.weight(r), d / r, tol / std::abs(r)) << r;
    }
    EXPECT_GE(kernel.cost(r), 0.0);
    EXPECT_GE(kernel.weight(r), 0.0);
    EXPECT_LE(kernel.weight(r), 1.0);
  }
  // Quadratic near zero: weight 1, cost r^2 / 2.
  EXPECT_DOUBLE_EQ(kernel.weight(0.0), 1.0);
  EXPECT_NEAR(kernel.cost(1e-4), 0.5e-8, 1e-15);
  // Symmetric.
  for (double r : kResiduals) EXPECT_DOUBLE_EQ(kernel.cost(r), kernel.cost(-r));
}

TEST(RobustKernel, SquaredKernelIsLeastSquares) {
  const SquaredKernel<double> k;
  expectConsistent(k);
  EXPECT_DOUBLE_EQ(k.cost(3.0), 4.5);
  EXPECT_DOUBLE_EQ(k.weight(100.0), 1.0);
}

TEST(RobustKernel, HuberWeightIsDerivativeOverResidual) {
  const HuberKernel<double> k(kThreshold);
  expectConsistent(k);
  EXPECT_DOUBLE_EQ(k.threshold(), kThreshold);
  // Hand-computed values: quadratic inside, linear outside, continuous at k.
  EXPECT_DOUBLE_EQ(k.cost(1.0), 0.5);
  EXPECT_DOUBLE_EQ(k.cost(3.0), 1.5 * (3.0 - 0.75));
  EXPECT_DOUBLE_EQ(k.weight(3.0), 0.5);
  EXPECT_DOUBLE_EQ(k.weight(-6.0), 0.25);
  EXPECT_NEAR(k.cost(kThreshold - 1e-12), k.cost(kThreshold + 1e-12), 1e-11);
  EXPECT_DOUBLE_EQ(k.derivative(-100.0), -kThreshold);
}

TEST(RobustKernel, CauchyWeightIsDerivativeOverResidual) {
  const CauchyKernel<double> k(kThreshold);
  expectConsistent(k);
  EXPECT_DOUBLE_EQ(k.weight(kThreshold), 0.5);
  EXPECT_NEAR(k.cost(kThreshold), 0.5 * kThreshold * kThreshold * std::log(2.0), 1e-15);
  // Never rejects completely, weight decreases with |r|.
  EXPECT_GT(k.weight(1e3), 0.0);
  EXPECT_LT(k.weight(3.0), k.weight(2.0));
}

TEST(RobustKernel, TukeyWeightIsDerivativeOverResidual) {
  const TukeyKernel<double> k(kThreshold);
  expectConsistent(k);
  EXPECT_DOUBLE_EQ(k.weight(2.0), 0.0);
  EXPECT_DOUBLE_EQ(k.cost(2.0), kThreshold * kThreshold / 6);
  EXPECT_DOUBLE_EQ(k.cost(100.0), kThreshold * kThreshold / 6);
  const double u = 1 - (0.75 / kThreshold) * (0.75 / kThreshold);
  EXPECT_DOUBLE_EQ(k.weight(0.75), u * u);
  EXPECT_NEAR(k.cost(kThreshold - 1e-9), k.cost(kThreshold + 1e-9), 1e-12);
}

TEST(RobustKernel, FloatKernelsAgreeWithDouble) {
  const HuberKernel<float> hf(1.5f);
  const CauchyKernel<float> cf(1.5f);
  const TukeyKernel<float> tf(1.5f);
  const HuberKernel<double> hd(1.5);
  const CauchyKernel<double> cd(1.5);
  const TukeyKernel<double> td(1.5);
  for (double r : kResiduals) {
    const float rf = static_cast<float>(r);
    EXPECT_NEAR(hf.weight(rf), hd.weight(r), 1e-6);
    EXPECT_NEAR(cf.weight(rf), cd.weight(r), 1e-6);
    EXPECT_NEAR(tf.weight(rf), td.weight(r), 1e-6);
    EXPECT_NEAR(hf.cost(rf), hd.cost(r), 1e-5 * (1 + hd.cost(r)));
    EXPECT_NEAR(cf.cost(rf), cd.cost(r), 1e-5 * (1 + cd.cost(r)));
    EXPECT_NEAR(tf.cost(rf), td.cost(r), 1e-5 * (1 + td.cost(r)));
  }
}

TEST(RobustKernel, InvalidThresholdsAreRejected) {
  const double bad[] = {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(),
                        std::numeric_limits<double>::infinity()};
  for (double k : bad) {
    EXPECT_THROW(HuberKernel<double>{k}, ConfigError) << k;
    EXPECT_THROW(CauchyKernel<double>{k}, ConfigError) << k;
    EXPECT_THROW(TukeyKernel<double>{k}, ConfigError) << k;
  }
  EXPECT_THROW(HuberKernel<float>{-2.0f}, ConfigError);
  try {
    HuberKernel<double> k(-2.0);
    FAIL() << "no exception";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("Huber"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("-2"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ldsm
