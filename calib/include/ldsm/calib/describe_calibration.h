// Human-readable summaries of calibrations (for `ldsm info` and logs).
#pragma once

#include <string>

#include "ldsm/camera/calibration.h"

namespace ldsm::calib {

/// Two lines: the input model with its parameters, and the output mode with the resulting
/// pinhole and its field of view (or why it cannot be computed). No trailing newline.
std::string describe(const GeometricCalibration& calibration);

/// One line: whether a response is known (and its range) and the vignette's size and minimum.
std::string describe(const PhotometricCalibration& calibration);

}  // namespace ldsm::calib
