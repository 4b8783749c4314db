// Mathematical constants and angle units shared by core (one definition instead of a literal and
// a conversion per file).
#pragma once

namespace ldsm {

inline constexpr double kPi = 3.14159265358979323846;

/// Radians in degrees (r * 180 / pi, in that order).
constexpr double degrees(double radians) {
  return radians * 180.0 / kPi;
}
/// Degrees in radians (d * pi / 180, in that order).
constexpr double radians(double degrees) {
  return degrees * kPi / 180.0;
}

}  // namespace ldsm
