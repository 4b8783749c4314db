// KITTI odometry calib.txt: lines "P0: p00 p01 ... p23", the 3x4 projection matrices of the
// rectified cameras 0..3 (row-major). The images are already rectified: the result is an
// undistorted pinhole with output mode `none` at the input size.
#pragma once

#include <string>

#include "ldsm/camera/calibration.h"

namespace ldsm::calib {

/// Reads P<camera> from a KITTI calib.txt for images of width x height (not stored in the file).
/// Throws ldsm::InputError "path:line: what" when the line is missing, does not hold 12 finite
/// numbers, is not a rectified pinhole projection (non-zero skew, last row not [0 0 1 t]) or
/// has a non-positive focal length, or when the size is not positive.
GeometricCalibration readKittiCalib(const std::string& path, int camera, int width, int height);

/// Same from the file's text; `name` stands for the path in messages.
GeometricCalibration parseKittiCalib(const std::string& text, const std::string& name, int camera,
                                     int width, int height);

}  // namespace ldsm::calib
