#include "ldsm/calib/kitti_calib.h"

#include "ldsm/camera/camera_model.h"
#include "ldsm/error.h"
#include "text_file.h"

namespace ldsm::calib {

GeometricCalibration parseKittiCalib(const std::string& text, const std::string& name, int camera,
                                     int width, int height) {
  if (width <= 0 || height <= 0)
    throw InputError(name + ": the image size must be given for a KITTI calibration (got " +
                     std::to_string(width) + "x" + std::to_string(height) + ")");
  if (camera < 0)
    throw InputError(name + ": camera index must not be negative (got " + std::to_string(camera) +
                     ")");
  const std::string key = "P" + std::to_string(camera) + ":";
  for (const auto& line : detail::contentLines(text)) {
    if (line.tokens[0] != key) continue;
    if (line.tokens.size() != 13)
      throw InputError(atLine(name, line.number,
                              key + " needs 12 numbers (a 3x4 projection matrix), found " +
                                  std::to_string(line.tokens.size() - 1)));
    double P[12];
    for (int i = 0; i < 12; ++i)
      P[i] = detail::parseNumber(line.tokens[1 + i], name, line.number,
                                 key + " value " + std::to_string(i + 1));
    const auto fail = [&](const std::string& what) {
      throw InputError(atLine(name, line.number, key + " " + what));
    };
    if (P[0] <= 0) fail("fx (value 1) must be positive (got " + line.tokens[1] + ")");
    if (P[5] <= 0) fail("fy (value 6) must be positive (got " + line.tokens[6] + ")");
    if (P[1] != 0) fail("has a non-zero skew (value 2): not a rectified pinhole");
    if (P[4] != 0 || P[8] != 0 || P[9] != 0 || P[10] != 1)
      fail("is not a rectified pinhole projection [fx 0 cx tx; 0 fy cy ty; 0 0 1 tz]");
    GeometricCalibration calib;
    calib.input.model = CameraModelType::Pinhole;
    calib.input.fx = P[0];
    calib.input.fy = P[5];
    calib.input.cx = P[2];
    calib.input.cy = P[6];
    calib.input.width = width;
    calib.input.height = height;
    calib.output.mode = OutputMode::None;
    calib.output.width = width;
    calib.output.height = height;
    validateIntrinsics(calib.input);
    return calib;
  }
  throw InputError(name + ": no line '" + key + "' (KITTI calib.txt has P0: to P3:)");
}

GeometricCalibration readKittiCalib(const std::string& path, int camera, int width, int height) {
  return parseKittiCalib(detail::readTextFile(path), path, camera, width, height);
}

}  // namespace ldsm::calib
