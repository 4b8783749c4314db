// A starting calibration for a camera nobody calibrated: an undistorted pinhole with the given
// horizontal field of view, square pixels and the principal point at the image centre. The
// online refinement (config section calibration) then corrects focal length, principal point
// and a radial distortion while the camera moves.
#pragma once

#include "ldsm/camera/calibration.h"

namespace ldsm::calib {

/// Smallest and largest horizontal field of view accepted, degrees.
constexpr double kMinGuessFovDeg = 20.0;
constexpr double kMaxGuessFovDeg = 160.0;

/// Pinhole fx = fy = (width / 2) / tan(fov / 2), cx = (width - 1) / 2, cy = (height - 1) / 2,
/// output mode none. Throws ldsm::ConfigError naming --fov when the field of view is outside
/// [kMinGuessFovDeg, kMaxGuessFovDeg] or not finite, ldsm::InputError on a non-positive size.
GeometricCalibration pinholeFromFieldOfView(int width, int height, double horizontal_fov_deg);

}  // namespace ldsm::calib
