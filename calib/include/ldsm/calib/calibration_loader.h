// Geometric calibration from any supported file, the format chosen by content.
#pragma once

#include <string>

#include "ldsm/camera/calibration.h"

namespace ldsm::calib {

enum class CalibrationFormat {
  DsoCamera,   ///< DSO camera.txt (dso_camera_file.h)
  KalibrYaml,  ///< EuRoC sensor.yaml or Kalibr camchain.yaml (kalibr_yaml.h)
  Kitti,       ///< KITTI calib.txt (kitti_calib.h)
};

/// Guesses the format of a calibration file's text: KITTI when a line starts with "P<n>:", YAML
/// when it starts with a "%YAML" directive or has camera_model / intrinsics / cam<n> keys,
/// otherwise DSO camera.txt.
CalibrationFormat detectCalibrationFormat(const std::string& text);

/// Reads a camera.txt, a EuRoC/Kalibr YAML (camera cam0) or a KITTI calib.txt (camera P0; the
/// image size width x height must then be given, it is not in the file). Throws
/// ldsm::InputError "path:line: what" like the individual readers.
GeometricCalibration loadGeometricCalibration(const std::string& path, int width = 0,
                                              int height = 0);

}  // namespace ldsm::calib
