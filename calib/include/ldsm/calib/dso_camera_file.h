// DSO's camera.txt format (as read by DSO and TUM-Mono):
//   line 1: model and intrinsics of the input images, one of
//             Pinhole fx fy cx cy [0]
//             RadTan fx fy cx cy k1 k2 p1 p2
//             EquiDistant fx fy cx cy k1 k2 k3 k4      (also KannalaBrandt)
//             FOV fx fy cx cy omega                    (also ATAN)
//             fx fy cx cy omega                        (old style: FOV, or pinhole if omega = 0)
//           When fx fy cx cy are all < 1 they are relative to the input size, as in DSO:
//           fx * width, fy * height, cx * width - 0.5, cy * height - 0.5.
//   line 2: input width height
//   line 3: crop | full | none | fx fy cx cy 0 (explicit output pinhole; relative to the output
//           size when all four are < 1, otherwise in output pixels)
//   line 4: output width height
// Blank lines and lines starting with '#' are ignored. Model and mode names are case-insensitive.
#pragma once

#include <string>

#include "ldsm/camera/calibration.h"

namespace ldsm::calib {

/// Reads a camera.txt. Throws ldsm::InputError "path:line: what" naming the field on: a missing
/// file or line, a wrong number count, a value that is not a number or not finite, a
/// non-positive focal length or size, an unknown model or output mode, a crop/full output larger
/// than the input, mode none with a distorted input, and content after line 4.
GeometricCalibration readDsoCameraFile(const std::string& path);

/// Parses the text of a camera.txt; `name` is used in error messages in place of the path.
GeometricCalibration parseDsoCameraFile(const std::string& text, const std::string& name);

/// The camera.txt text of `calibration` (input intrinsics in pixels; numbers written so that
/// they read back exactly). Throws ldsm::InputError when the calibration is invalid.
std::string formatDsoCameraFile(const GeometricCalibration& calibration);

/// Writes formatDsoCameraFile() to `path` (ldsm::Error when it cannot be written).
void writeDsoCameraFile(const std::string& path, const GeometricCalibration& calibration);

}  // namespace ldsm::calib
