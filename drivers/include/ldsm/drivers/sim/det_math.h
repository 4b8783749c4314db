// Deterministic elementary functions and hashing for the synthetic renderer.
//
// The standard library's sin/cos/exp/log/pow may differ in their last bits between C libraries and
// architectures, which would make rendered frames differ between machines. These versions use
// only IEEE-754 +, -, *, / and exact operations (frexp/ldexp, integer conversion), evaluated in a
// fixed order, so every conforming platform computes the same bits (build with
// -ffp-contract=off so that no multiply-add is fused).
//
// Accuracy (checked against long double in tests/unit/sim/det_math_test.cpp): detSin/detCos
// absolute error < 3e-16 for |x| <= 1e5; detExp relative error < 3e-16; detLog error
// < 3e-16 * max(1, |log x|); detPow relative error about 3e-16 * (1 + |y log x|).
#pragma once

#include <cstdint>

namespace ldsm::drivers::sim {

inline constexpr double kPi = 3.14159265358979323846;

/// Sine of x (radians). Cody-Waite reduction by pi/2 and Taylor polynomials on [-pi/4, pi/4].
double detSin(double x);
/// Cosine of x (radians).
double detCos(double x);
/// Sine and cosine of x with one range reduction.
void detSinCos(double x, double& s, double& c);
/// Tangent of x (radians), detSin / detCos.
double detTan(double x);
/// e^x. Returns +inf above 709.78 and 0 below -745.
double detExp(double x);
/// Natural logarithm. Returns -inf for 0 and NaN for negative x.
double detLog(double x);
/// Base-2 logarithm, detLog(x) / ln 2.
double detLog2(double x);
/// x^y for x > 0 (exp(y log x)); 0 for x == 0 and y > 0; NaN for x < 0.
double detPow(double x, double y);

/// Degrees to radians.
inline double degToRad(double deg) {
  return deg * (kPi / 180.0);
}

/// A 32-bit integer hash with good avalanche (two multiply-xorshift rounds).
inline std::uint32_t hash32(std::uint32_t x) {
  x ^= x >> 16;
  x *= 0x85ebca6bu;
  x ^= x >> 13;
  x *= 0xc2b2ae35u;
  x ^= x >> 16;
  return x;
}

/// Hash of two integers (order matters).
inline std::uint32_t hash32(std::uint32_t a, std::uint32_t b) {
  return hash32(a ^ hash32(b + 0x9e3779b9u));
}

/// Hash of three integers.
inline std::uint32_t hash32(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  return hash32(hash32(a, b), c);
}

/// A hash mapped to [0, 1) with 24 bits of resolution (exactly representable in float and double).
inline double hashToUnit(std::uint32_t h) {
  return static_cast<double>(h >> 8) * (1.0 / 16777216.0);
}

/// Uniform value in [0, 1) from three integer keys.
inline double hashUnit(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  return hashToUnit(hash32(a, b, c));
}

}  // namespace ldsm::drivers::sim
