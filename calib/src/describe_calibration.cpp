#include "ldsm/calib/describe_calibration.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "ldsm/camera/camera_model.h"
#include "ldsm/camera/rectifier.h"
#include "ldsm/error.h"

namespace ldsm::calib {
namespace {

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.6g", v);
  return buf;
}

std::string size(int w, int h) {
  return std::to_string(w) + "x" + std::to_string(h);
}

/// Field of view (degrees) of a pinhole along one axis, from pixel edge to pixel edge.
double fieldOfView(double f, double c, int n) {
  constexpr double kDeg = 57.29577951308232;
  return (std::atan((c + 0.5) / f) + std::atan((n - 0.5 - c) / f)) * kDeg;
}

const char* distortionNames(CameraModelType type, std::size_t i) {
  static const char* kRadTan[] = {"k1", "k2", "p1", "p2"};
  static const char* kEqui[] = {"k1", "k2", "k3", "k4"};
  if (type == CameraModelType::RadTan && i < 4) return kRadTan[i];
  if (type == CameraModelType::Equidistant && i < 4) return kEqui[i];
  if (type == CameraModelType::Fov && i == 0) return "omega";
  return "d";
}

}  // namespace

std::string describe(const GeometricCalibration& calibration) {
  const CameraIntrinsics& in = calibration.input;
  std::string s = "input: " + std::string(cameraModelName(in.model)) + " " +
                  size(in.width, in.height) + " fx=" + num(in.fx) + " fy=" + num(in.fy) +
                  " cx=" + num(in.cx) + " cy=" + num(in.cy);
  for (std::size_t i = 0; i < in.distortion.size(); ++i)
    s += std::string(" ") + distortionNames(in.model, i) + "=" + num(in.distortion[i]);
  const RectificationSpec& out = calibration.output;
  s += "\noutput: ";
  switch (out.mode) {
    case OutputMode::Crop:
      s += "crop";
      break;
    case OutputMode::Full:
      s += "full";
      break;
    case OutputMode::None:
      s += "none";
      break;
    case OutputMode::Explicit:
      s += std::string("explicit (") + (out.relative ? "relative " : "pixels ") + num(out.fx) +
           " " + num(out.fy) + " " + num(out.cx) + " " + num(out.cy) + ")";
      break;
  }
  s += " " + size(out.width, out.height);
  try {
    const PinholeIntrinsics p = computeOutputIntrinsics(*makeCameraModel(in), out);
    s += " -> pinhole fx=" + num(p.fx) + " fy=" + num(p.fy) + " cx=" + num(p.cx) +
         " cy=" + num(p.cy) + ", field of view " + num(fieldOfView(p.fx, p.cx, p.width)) + "x" +
         num(fieldOfView(p.fy, p.cy, p.height)) + " deg";
  } catch (const InputError& e) {
    s += std::string(" (invalid: ") + e.what() + ")";
  }
  return s;
}

std::string describe(const PhotometricCalibration& calibration) {
  std::string s = "photometric: response ";
  if (calibration.has_response) {
    s += "G^-1 in [" + num(calibration.inverse_response.front()) + ", " +
         num(calibration.inverse_response.back()) + "]";
  } else {
    s += "unknown (linear)";
  }
  s += ", vignette ";
  const ImageF& v = calibration.vignette;
  if (v.empty()) return s + "none";
  float lo = v(0, 0);
  for (int y = 0; y < v.height(); ++y)
    for (int x = 0; x < v.width(); ++x) lo = std::min(lo, v(x, y));
  return s + size(v.width(), v.height()) + " min " + num(lo);
}

}  // namespace ldsm::calib
