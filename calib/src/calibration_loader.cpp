#include "ldsm/calib/calibration_loader.h"

#include <regex>

#include "ldsm/calib/dso_camera_file.h"
#include "ldsm/calib/kalibr_yaml.h"
#include "ldsm/calib/kitti_calib.h"
#include "text_file.h"

namespace ldsm::calib {

CalibrationFormat detectCalibrationFormat(const std::string& text) {
  static const std::regex kKittiKey("^P[0-9]+:$");
  static const std::regex kYamlKey("^(camera_model|intrinsics|cam[0-9]+|sensor_type):.*");
  const auto lines = detail::contentLines(text);
  if (!lines.empty() && lines.front().tokens[0].rfind("%YAML", 0) == 0)
    return CalibrationFormat::KalibrYaml;
  for (const auto& line : lines)
    if (std::regex_match(line.tokens[0], kKittiKey)) return CalibrationFormat::Kitti;
  for (const auto& line : lines)
    if (std::regex_match(line.tokens[0], kYamlKey)) return CalibrationFormat::KalibrYaml;
  return CalibrationFormat::DsoCamera;
}

GeometricCalibration loadGeometricCalibration(const std::string& path, int width, int height) {
  const std::string text = detail::readTextFile(path);
  switch (detectCalibrationFormat(text)) {
    case CalibrationFormat::Kitti:
      return parseKittiCalib(text, path, 0, width, height);
    case CalibrationFormat::KalibrYaml:
      return parseKalibrCameraYaml(text, path);
    case CalibrationFormat::DsoCamera:
      break;
  }
  return parseDsoCameraFile(text, path);
}

}  // namespace ldsm::calib
