// Mathematical constants shared by core (one definition instead of a literal per file).
#pragma once

namespace ldsm {

inline constexpr double kPi = 3.14159265358979323846;

}  // namespace ldsm
