// Accuracy of the deterministic elementary functions against long double references.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "ldsm/drivers/sim/det_math.h"

namespace ldsm::drivers::sim {
namespace {

TEST(DetMath, SinCosMatchReferenceOverWideRange) {
  double max_err = 0.0;
  for (int i = -200000; i <= 200000; ++i) {
    const double x = i * 0.5123456789;  // up to ~1e5
    const long double lx = x;
    max_err = std::max(max_err, static_cast<double>(std::fabs(detSin(x) - std::sin(lx))));
    max_err = std::max(max_err, static_cast<double>(std::fabs(detCos(x) - std::cos(lx))));
  }
  EXPECT_LT(max_err, 3e-16);  // exact Cody-Waite reduction: no growth with |x|
  double small_err = 0.0;
  for (int i = -10000; i <= 10000; ++i) {
    const double x = i * 3.14159e-4;
    const long double lx = x;
    small_err = std::max(small_err, static_cast<double>(std::fabs(detSin(x) - std::sin(lx))));
    small_err = std::max(small_err, static_cast<double>(std::fabs(detCos(x) - std::cos(lx))));
  }
  EXPECT_LT(small_err, 3e-16);
}

TEST(DetMath, SinCosKnownValuesAndIdentities) {
  EXPECT_EQ(detSin(0.0), 0.0);
  EXPECT_EQ(detCos(0.0), 1.0);
  EXPECT_NEAR(detSin(kPi / 6), 0.5, 2.3e-16);  // kPi / 6 is not exactly pi / 6
  EXPECT_NEAR(detCos(kPi / 3), 0.5, 2.3e-16);
  EXPECT_NEAR(detTan(kPi / 4), 1.0, 1e-15);
  for (double x = -20.0; x < 20.0; x += 0.37) {
    double s, c;
    detSinCos(x, s, c);
    EXPECT_EQ(s, detSin(x));
    EXPECT_EQ(c, detCos(x));
    EXPECT_NEAR(s * s + c * c, 1.0, 1e-15);
    EXPECT_EQ(detSin(-x), -detSin(x));
  }
  EXPECT_TRUE(std::isnan(detSin(std::numeric_limits<double>::infinity())));
}

TEST(DetMath, ExpLogPowMatchReference) {
  double exp_rel = 0.0, log_abs = 0.0, pow_rel = 0.0;
  for (int i = -7000; i <= 7000; ++i) {
    const double x = i * 0.1013;
    const long double ref = std::exp(static_cast<long double>(x));
    exp_rel = std::max(exp_rel, static_cast<double>(std::fabs((detExp(x) - ref) / ref)));
  }
  for (int i = 1; i < 20000; ++i) {
    const double x = std::ldexp(1.0 + (i % 997) / 997.0, i / 20 - 500);
    const long double ref = std::log(static_cast<long double>(x));
    log_abs = std::max(
        log_abs, static_cast<double>(std::fabs(detLog(x) - ref) / std::max(1.0L, std::fabs(ref))));
  }
  for (double b = 0.01; b < 10.0; b *= 1.37)
    for (double e = -3.0; e < 3.0; e += 0.29) {
      const long double ref = std::pow(static_cast<long double>(b), static_cast<long double>(e));
      pow_rel = std::max(pow_rel, static_cast<double>(std::fabs((detPow(b, e) - ref) / ref)));
    }
  EXPECT_LT(exp_rel, 3e-16);
  EXPECT_LT(log_abs, 3e-16);  // relative to max(1, |log x|)
  EXPECT_LT(pow_rel, 5e-15);  // |y log x| up to ~14 here
  EXPECT_NEAR(detExp(1.0), 2.718281828459045, 4.5e-16);
  EXPECT_EQ(detLog(1.0), 0.0);
  EXPECT_NEAR(detLog2(8.0), 3.0, 1e-15);
  EXPECT_EQ(detPow(0.0, 2.0), 0.0);
  EXPECT_EQ(detPow(5.0, 0.0), 1.0);
  EXPECT_TRUE(std::isnan(detLog(-1.0)));
  EXPECT_TRUE(std::isnan(detPow(-2.0, 0.5)));
  EXPECT_EQ(detExp(1000.0), std::numeric_limits<double>::infinity());
  EXPECT_EQ(detExp(-1000.0), 0.0);
  EXPECT_EQ(detLog(0.0), -std::numeric_limits<double>::infinity());
}

TEST(DetMath, HashIsWellSpreadAndKeyed) {
  // Uniform in [0, 1): mean and variance of many hashes, and neighbouring keys uncorrelated.
  double sum = 0.0, sum2 = 0.0, corr = 0.0;
  const int n = 200000;
  double prev = hashUnit(0, 7, 9);
  for (int i = 1; i <= n; ++i) {
    const double u = hashUnit(static_cast<std::uint32_t>(i), 7, 9);
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    sum += u;
    sum2 += u * u;
    corr += (u - 0.5) * (prev - 0.5);
    prev = u;
  }
  const double mean = sum / n, var = sum2 / n - mean * mean;
  EXPECT_NEAR(mean, 0.5, 0.005);
  EXPECT_NEAR(var, 1.0 / 12.0, 0.002);
  EXPECT_NEAR(corr / n / (1.0 / 12.0), 0.0, 0.02);
  EXPECT_NE(hash32(1, 2), hash32(2, 1));
  EXPECT_EQ(hash32(123u, 456u, 789u), hash32(123u, 456u, 789u));
}

}  // namespace
}  // namespace ldsm::drivers::sim
