// Camera intrinsics used by the camera tests.
#pragma once

#include <string>
#include <vector>

#include "ldsm/camera/calibration.h"

namespace ldsm::test {

inline CameraIntrinsics makeIntrinsics(CameraModelType model, double fx, double fy, double cx,
                                       double cy, std::vector<double> distortion, int width,
                                       int height) {
  CameraIntrinsics in;
  in.model = model;
  in.fx = fx;
  in.fy = fy;
  in.cx = cx;
  in.cy = cy;
  in.distortion = std::move(distortion);
  in.width = width;
  in.height = height;
  return in;
}

inline CameraIntrinsics pinholeIntrinsics() {
  return makeIntrinsics(CameraModelType::Pinhole, 400, 410, 321.3, 238.7, {}, 640, 480);
}
/// Strong barrel distortion (EuRoC-like).
inline CameraIntrinsics radTanIntrinsics() {
  return makeIntrinsics(CameraModelType::RadTan, 458.654, 457.296, 367.215, 248.375,
                        {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05}, 752, 480);
}
/// Pincushion distortion with noticeable tangential terms.
inline CameraIntrinsics pincushionIntrinsics() {
  return makeIntrinsics(CameraModelType::RadTan, 500, 505, 315, 245, {0.12, 0.02, 0.002, -0.001},
                        640, 480);
}
/// A fisheye of about 190 degrees diagonal field of view.
inline CameraIntrinsics equidistantIntrinsics() {
  return makeIntrinsics(CameraModelType::Equidistant, 190.9, 190.8, 254.9, 256.9,
                        {0.0034, 0.0007, -0.0021, 0.0002}, 512, 512);
}
inline CameraIntrinsics fovIntrinsics() {
  return makeIntrinsics(CameraModelType::Fov, 300, 310, 319.5, 239.5, {0.9}, 640, 480);
}

struct NamedIntrinsics {
  std::string name;
  CameraIntrinsics intrinsics;
};

inline std::vector<NamedIntrinsics> allSampleCameras() {
  return {{"pinhole", pinholeIntrinsics()},
          {"radtan", radTanIntrinsics()},
          {"pincushion", pincushionIntrinsics()},
          {"equidistant", equidistantIntrinsics()},
          {"fov", fovIntrinsics()},
          {"fov_tiny_omega",
           makeIntrinsics(CameraModelType::Fov, 300, 300, 320, 240, {1e-6}, 640, 480)},
          {"fov_zero_omega",
           makeIntrinsics(CameraModelType::Fov, 300, 300, 320, 240, {0.0}, 640, 480)}};
}

}  // namespace ldsm::test
