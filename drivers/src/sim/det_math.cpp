// Deterministic elementary functions: see det_math.h for the contract. Polynomials are truncated
// Taylor series evaluated with Horner's scheme; the truncation error of each is stated below.
#include "ldsm/drivers/sim/det_math.h"

#include <cmath>
#include <limits>

namespace ldsm::drivers::sim {
namespace {

// pi/2 split into three parts; the first two have 33 significant bits so k * part is exact for
// |k| < 2^20.
constexpr double kPio2Hi = 1.5707963267341256;
constexpr double kPio2Mid = 6.077100506303966e-11;
constexpr double kPio2Lo = 2.0222662487959506e-21;
constexpr double kTwoOverPi = 0.6366197723675814;
// ln 2 split; the high part has 32 significant bits so k * part is exact for |k| < 2^21.
constexpr double kLn2Hi = 0.6931471803691238;
constexpr double kLn2Lo = 1.9082149292705877e-10;
constexpr double kInvLn2 = 1.4426950408889634;
constexpr double kSqrtHalf = 0.7071067811865476;

// Nearest integer of x (ties away from zero), for |x| < 2^52.
double roundToInt(double x) {
  return x >= 0.0 ? std::floor(x + 0.5) : -std::floor(-x + 0.5);
}

// sin(r) for |r| <= pi/4: Taylor to r^15; truncation error < (pi/4)^17 / 17! < 5e-17.
double sinPoly(double r) {
  const double r2 = r * r;
  double p = -1.0 / 1307674368000.0;  // -1/15!
  p = p * r2 + 1.0 / 6227020800.0;    // 1/13!
  p = p * r2 - 1.0 / 39916800.0;      // -1/11!
  p = p * r2 + 1.0 / 362880.0;        // 1/9!
  p = p * r2 - 1.0 / 5040.0;          // -1/7!
  p = p * r2 + 1.0 / 120.0;           // 1/5!
  p = p * r2 - 1.0 / 6.0;             // -1/3!
  return r + r * (r2 * p);
}

// cos(r) for |r| <= pi/4: Taylor to r^16; truncation error < (pi/4)^18 / 18! < 3e-18.
double cosPoly(double r) {
  const double r2 = r * r;
  double p = 1.0 / 20922789888000.0;  // 1/16!
  p = p * r2 - 1.0 / 87178291200.0;   // -1/14!
  p = p * r2 + 1.0 / 479001600.0;     // 1/12!
  p = p * r2 - 1.0 / 3628800.0;       // -1/10!
  p = p * r2 + 1.0 / 40320.0;         // 1/8!
  p = p * r2 - 1.0 / 720.0;           // -1/6!
  p = p * r2 + 1.0 / 24.0;            // 1/4!
  p = p * r2 - 0.5;                   // -1/2!
  return 1.0 + r2 * p;
}

}  // namespace

void detSinCos(double x, double& s, double& c) {
  if (!std::isfinite(x)) {
    s = c = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  const double k = roundToInt(x * kTwoOverPi);
  const double r = ((x - k * kPio2Hi) - k * kPio2Mid) - k * kPio2Lo;
  const double sr = sinPoly(r);
  const double cr = cosPoly(r);
  // Quadrant k mod 4 (k may be negative).
  const long long q = static_cast<long long>(k) & 3;
  switch (q) {
    case 0:
      s = sr;
      c = cr;
      break;
    case 1:
      s = cr;
      c = -sr;
      break;
    case 2:
      s = -sr;
      c = -cr;
      break;
    default:
      s = -cr;
      c = sr;
      break;
  }
}

double detSin(double x) {
  double s, c;
  detSinCos(x, s, c);
  return s;
}

double detCos(double x) {
  double s, c;
  detSinCos(x, s, c);
  return c;
}

double detTan(double x) {
  double s, c;
  detSinCos(x, s, c);
  return s / c;
}

double detExp(double x) {
  if (std::isnan(x)) return x;
  if (x > 709.782712893384) return std::numeric_limits<double>::infinity();
  if (x < -745.2) return 0.0;
  const double k = roundToInt(x * kInvLn2);
  const double r = (x - k * kLn2Hi) - k * kLn2Lo;  // |r| <= 0.347
  // Taylor to r^13; truncation error < 0.347^14 / 14! < 5e-18 (relative).
  double p = 1.0 / 6227020800.0;  // 1/13!
  p = p * r + 1.0 / 479001600.0;  // 1/12!
  p = p * r + 1.0 / 39916800.0;   // 1/11!
  p = p * r + 1.0 / 3628800.0;    // 1/10!
  p = p * r + 1.0 / 362880.0;     // 1/9!
  p = p * r + 1.0 / 40320.0;      // 1/8!
  p = p * r + 1.0 / 5040.0;       // 1/7!
  p = p * r + 1.0 / 720.0;        // 1/6!
  p = p * r + 1.0 / 120.0;        // 1/5!
  p = p * r + 1.0 / 24.0;         // 1/4!
  p = p * r + 1.0 / 6.0;          // 1/3!
  p = p * r + 0.5;                // 1/2!
  p = p * r + 1.0;
  p = p * r + 1.0;
  // ldexp is exact; split the scaling so subnormal results do not overflow the exponent range.
  const int ki = static_cast<int>(k);
  if (ki < -1000) return std::ldexp(std::ldexp(p, ki + 600), -600);
  return std::ldexp(p, ki);
}

double detLog(double x) {
  if (std::isnan(x) || x < 0.0) return std::numeric_limits<double>::quiet_NaN();
  if (x == 0.0) return -std::numeric_limits<double>::infinity();
  if (std::isinf(x)) return x;
  int e = 0;
  double m = std::frexp(x, &e);  // exact: x = m * 2^e, m in [0.5, 1)
  if (m < kSqrtHalf) {
    m *= 2.0;
    --e;
  }
  // log m = 2 atanh(s), s = (m - 1) / (m + 1), |s| <= 0.1716; series to s^21, truncation error
  // < 2 * 0.1716^23 / 23 < 2e-19.
  const double s = (m - 1.0) / (m + 1.0);
  const double s2 = s * s;
  double p = 1.0 / 21.0;
  p = p * s2 + 1.0 / 19.0;
  p = p * s2 + 1.0 / 17.0;
  p = p * s2 + 1.0 / 15.0;
  p = p * s2 + 1.0 / 13.0;
  p = p * s2 + 1.0 / 11.0;
  p = p * s2 + 1.0 / 9.0;
  p = p * s2 + 1.0 / 7.0;
  p = p * s2 + 1.0 / 5.0;
  p = p * s2 + 1.0 / 3.0;
  const double log_m = 2.0 * s + 2.0 * s * (s2 * p);
  const double de = static_cast<double>(e);
  return (de * kLn2Hi + log_m) + de * kLn2Lo;
}

double detLog2(double x) {
  return detLog(x) * kInvLn2;
}

double detPow(double x, double y) {
  if (std::isnan(x) || std::isnan(y) || x < 0.0) return std::numeric_limits<double>::quiet_NaN();
  if (y == 0.0) return 1.0;
  if (x == 0.0) return y > 0.0 ? 0.0 : std::numeric_limits<double>::infinity();
  return detExp(y * detLog(x));
}

}  // namespace ldsm::drivers::sim
