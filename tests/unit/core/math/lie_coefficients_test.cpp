// The scalar coefficients of the Lie-group formulas against independent long-double references:
// power series (with many more terms than the implementation keeps) and Gauss-Legendre quadrature
// of the defining integrals.
#include "math/lie_coefficients.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <vector>

namespace ldsm::lie {
namespace {

using LD = long double;

// Angles around every switch of the implementation (series below 0.01 rad) and up to pi.
const double kThetas[] = {0.0,  1e-12, 1e-8, 1e-5, 1e-3, 0.0099999, 0.01, 0.0100001,
                          0.02, 0.1,   0.5,  1.0,  2.0,  3.0,       M_PI};

// sum_{k>=k0} term(k) until the terms vanish in long double.
LD series(int k0, const std::function<LD(int)>& term) {
  LD sum = 0;
  for (int k = k0; k < k0 + 40; ++k) sum += term(k);
  return sum;
}

LD factorial(int n) {
  LD f = 1;
  for (int i = 2; i <= n; ++i) f *= i;
  return f;
}

// Checks f(theta^2) against ref(theta) to a relative 4e-15 at every test angle: the series cover
// the ranges where the closed forms would cancel.
void expectAccurate(const char* name, const std::function<double(double)>& f,
                    const std::function<LD(LD)>& ref) {
  for (double theta : kThetas) {
    const LD r = ref(theta);
    const double got = f(theta * theta);
    const double err = static_cast<double>(std::fabs(static_cast<LD>(got) - r));
    EXPECT_LE(err, 4e-15 * static_cast<double>(std::fabs(r))) << name << " at theta " << theta;
  }
}

TEST(LieCoefficients, SO3AndSE3CoefficientsMatchTheirSeries) {
  if (std::numeric_limits<LD>::digits <= std::numeric_limits<double>::digits)
    GTEST_SKIP() << "long double is no wider than double on this platform (e.g. 32-bit ARM): no "
                    "extended-precision reference";
  expectAccurate(
      "sin(t/2)/t", [](double t2) { return sinHalfOverTheta(t2); },
      [](LD t) {
        return series(0, [&](int k) {
          return std::pow(-1.0L, k) * std::pow(t, 2 * k) /
                 (std::pow(2.0L, 2 * k + 1) * factorial(2 * k + 1));
        });
      });
  expectAccurate(
      "cos(t/2)", [](double t2) { return cosHalf(t2); }, [](LD t) { return std::cos(t / 2); });
  expectAccurate(
      "(1-cos t)/t^2", [](double t2) { return oneMinusCosOverTheta2(t2); },
      [](LD t) {
        return series(0, [&](int k) {
          return std::pow(-1.0L, k) * std::pow(t, 2 * k) / factorial(2 * k + 2);
        });
      });
  expectAccurate(
      "(t-sin t)/t^3", [](double t2) { return thetaMinusSinOverTheta3(t2); },
      [](LD t) {
        return series(0, [&](int k) {
          return std::pow(-1.0L, k) * std::pow(t, 2 * k) / factorial(2 * k + 3);
        });
      });
  expectAccurate(
      "(t^2+2cos t-2)/(2t^4)", [](double t2) { return se3QCoefficient2(t2); },
      [](LD t) {
        return series(2, [&](int m) {
          return std::pow(-1.0L, m) * std::pow(t, 2 * m - 4) / factorial(2 * m);
        });
      });
  expectAccurate(
      "(2t-3sin t+t cos t)/(2t^5)", [](double t2) { return se3QCoefficient3(t2); },
      [](LD t) {
        return series(2, [&](int m) {
          return std::pow(-1.0L, m) * (m - 1) * std::pow(t, 2 * m - 4) / factorial(2 * m + 1);
        });
      });
  // 1/t^2 - cot(t/2)/(2t): Bernoulli series below 0.05, the long-double closed form above.
  expectAccurate(
      "inverse Jacobian", [](double t2) { return inverseJacobianCoefficient(t2); },
      [](LD t) -> LD {
        if (t >= 0.05L) return 1 / (t * t) - std::cos(t / 2) / (2 * t * std::sin(t / 2));
        const LD b[] = {1.0L / 6, -1.0L / 30, 1.0L / 42, -1.0L / 30, 5.0L / 66, -691.0L / 2730};
        LD sum = 0;
        for (int n = 1; n <= 6; ++n) {
          sum += std::pow(-1.0L, n + 1) * b[n - 1] * std::pow(t, 2 * n - 2) / factorial(2 * n);
        }
        return sum;
      });
}

TEST(LieCoefficients, QuaternionLogFactorIsTwoAtan2OverN) {
  for (double theta : kThetas) {
    const double n = std::sin(theta / 2);
    const double w = std::cos(theta / 2);
    const LD ref = n == 0 ? 2.0L / w : 2 * std::atan2(static_cast<LD>(n), static_cast<LD>(w)) / n;
    const double got = quaternionLogFactor(n * n, w);
    EXPECT_LE(std::fabs(got - static_cast<double>(ref)), 2e-15 * static_cast<double>(ref)) << theta;
  }
}

// Gauss-Legendre rule on [0, 1] (nodes by Newton's method on the Legendre polynomial).
class GaussLegendre {
 public:
  explicit GaussLegendre(int n) {
    for (int i = 1; i <= n; ++i) {
      LD z = std::cos(3.14159265358979323846264338327950288L * (i - 0.25L) / (n + 0.5L));
      LD dp = 0;
      for (int it = 0; it < 100; ++it) {
        LD p0 = 1;
        LD p1 = z;
        for (int k = 2; k <= n; ++k) {
          const LD p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
          p0 = p1;
          p1 = p2;
        }
        dp = n * (z * p1 - p0) / (z * z - 1);
        const LD step = p1 / dp;
        z -= step;
        if (std::fabs(step) < 1e-20L) break;
      }
      nodes_.push_back((z + 1) / 2);
      weights_.push_back(1 / ((1 - z * z) * dp * dp));  // 2 / (...) halved for [0, 1]
    }
  }
  LD integrate(const std::function<LD(LD)>& f) const {
    LD sum = 0;
    for (std::size_t i = 0; i < nodes_.size(); ++i) sum += weights_[i] * f(nodes_[i]);
    return sum;
  }

 private:
  std::vector<LD> nodes_;
  std::vector<LD> weights_;
};

TEST(LieCoefficients, GaussLegendreRuleIsExact) {
  if (std::numeric_limits<LD>::digits <= std::numeric_limits<double>::digits)
    GTEST_SKIP() << "long double is no wider than double on this platform (e.g. 32-bit ARM): no "
                    "extended-precision reference";
  const GaussLegendre gl(24);
  EXPECT_NEAR(static_cast<double>(gl.integrate([](LD t) { return t * t * t * t * t; })), 1.0 / 6,
              1e-17);
  EXPECT_LT(std::fabs(gl.integrate([](LD t) { return std::exp(t); }) - (std::exp(1.0L) - 1)),
            1e-18L);
}

TEST(LieCoefficients, ExpMomentsMatchQuadrature) {
  const GaussLegendre gl(24);
  for (double sigma : {0.0, 1e-12, -1e-8, 0.3, -0.7, 0.999999, 1.0, -1.0, 1.5, -2.5, 4.0}) {
    const ExpMoments<double, 15> m(sigma);
    for (int k = 0; k < 15; ++k) {
      const LD ref = gl.integrate([&](LD t) { return std::pow(t, k) * std::exp(sigma * t); });
      // The recurrence (|sigma| >= 1) amplifies the rounding of I_0-sized terms by up to
      // k! / |sigma|^k; the moments
      // only enter multiplied by theta^(k-1) / k!, which damps that again.
      const double amplification =
          std::abs(sigma) >= 1 ? factorial(k) / std::pow(std::abs(sigma), k) : 1.0;
      const double allowed = 2e-15 * static_cast<double>(ref) + 2e-15 * amplification * m.I[0];
      EXPECT_LE(std::fabs(m.I[k] - static_cast<double>(ref)), allowed)
          << "k " << k << " sigma " << sigma;
    }
  }
}

TEST(LieCoefficients, Sim3WCoefficientsMatchQuadrature) {
  const GaussLegendre gl(24);
  for (double sigma : {0.0, 1e-12, -1e-10, 1e-6, -1e-3, 0.3, -0.999, 1.0, -1.0, 1.7, -2.5}) {
    for (double theta : {0.0, 1e-12, 1e-8, 1e-5, 1e-3, 0.01, 0.1, 0.2999999, 0.3, 0.3000001, 0.5,
                         1.0, 2.0, 3.0, M_PI}) {
      const LD th = theta;
      const LD a = gl.integrate([&](LD t) { return std::exp(sigma * t); });
      const LD b = gl.integrate(
          [&](LD t) { return std::exp(sigma * t) * (th == 0 ? t : std::sin(th * t) / th); });
      const LD c = gl.integrate([&](LD t) {
        const LD s = std::sin(th * t / 2);
        return std::exp(sigma * t) * (th == 0 ? t * t / 2 : 2 * s * s / (th * th));
      });
      const Sim3WCoefficients<double> w(sigma, theta * theta);
      // Errors weighted as they enter W = a I + b hat(w) + c hat(w)^2 (|hat(w)| = theta).
      const double err = std::fabs(w.a - static_cast<double>(a)) +
                         std::fabs(w.b - static_cast<double>(b)) * theta +
                         std::fabs(w.c - static_cast<double>(c)) * theta * theta;
      EXPECT_LE(err, 1e-15 * static_cast<double>(a + b * th + c * th * th))
          << "sigma " << sigma << " theta " << theta;
      // And each coefficient on its own, relative, allowing the ~6 eps / theta^2 loss of the
      // closed form of c above 0.3 rad (it multiplies hat(w)^2, so W stays accurate).
      EXPECT_LE(std::fabs(w.b - static_cast<double>(b)), 4e-15 * static_cast<double>(b))
          << "sigma " << sigma << " theta " << theta;
      EXPECT_LE(std::fabs(w.c - static_cast<double>(c)),
                (4e-15 + (theta >= 0.3 ? 6e-15 / (theta * theta) : 0.0)) * static_cast<double>(c))
          << "sigma " << sigma << " theta " << theta;
    }
  }
}

}  // namespace
}  // namespace ldsm::lie
