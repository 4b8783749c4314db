// Camera intrinsics from YAML: EuRoC's sensor.yaml (camera_model, intrinsics, distortion_model,
// distortion_coefficients, resolution; the leading "%YAML:1.0" line of OpenCV is accepted) and
// Kalibr's camchain.yaml (a cam0 / cam1 ... section with camera_model, intrinsics,
// distortion_model, distortion_coeffs, resolution). The writer produces the camchain form.
//
// Supported: camera_model pinhole with distortion_model radtan / radial-tangential,
// equidistant, fov or none. Output (not stored in these files): `none` at the input size when the
// distortion is absent or all zero, otherwise `crop` at the input size (every output pixel
// valid, the engine sees no black border).
#pragma once

#include <string>

#include "ldsm/camera/calibration.h"

namespace ldsm::calib {

/// Reads the camera `camera` (a Kalibr camchain section; ignored for a flat EuRoC sensor.yaml).
/// Throws ldsm::InputError "path:line: what" on YAML syntax errors, missing or malformed keys,
/// unsupported models, non-finite values, non-positive focal lengths or sizes.
GeometricCalibration readKalibrCameraYaml(const std::string& path,
                                          const std::string& camera = "cam0");

/// Same from YAML text; `name` stands for the path in messages.
GeometricCalibration parseKalibrCameraYaml(const std::string& text, const std::string& name,
                                           const std::string& camera = "cam0");

/// Kalibr camchain text of the input camera of `calibration` as section `camera`: camera_model
/// pinhole, intrinsics, distortion_model (radtan, equidistant, fov or none), distortion_coeffs,
/// resolution; numbers read back exactly. The output mode is not stored (the reader infers it).
/// Throws ldsm::InputError when the intrinsics are invalid.
std::string formatKalibrCameraYaml(const GeometricCalibration& calibration,
                                   const std::string& camera = "cam0");

/// Writes formatKalibrCameraYaml() to `path` (ldsm::Error when it cannot be written).
void writeKalibrCameraYaml(const std::string& path, const GeometricCalibration& calibration,
                           const std::string& camera = "cam0");

}  // namespace ldsm::calib
