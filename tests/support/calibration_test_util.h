// Helpers of the calibration tool tests: known cameras, board poses that keep the board in view,
// and rendering board views with ldsm's synthetic calibration target.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "ldsm/calib/board_detection.h"
#include "ldsm/calib/camera_calibration.h"
#include "ldsm/camera/camera_model.h"
#include "ldsm/drivers/sim/calibration_target.h"
#include "ldsm/error.h"
#include "test_paths.h"

namespace ldsm::test {

constexpr int kWidth = 320;
constexpr int kHeight = 240;

inline CameraIntrinsics pinholeCamera() {
  CameraIntrinsics c;
  c.model = CameraModelType::Pinhole;
  c.fx = 262.5;
  c.fy = 259.0;
  c.cx = 161.3;
  c.cy = 118.2;
  c.width = kWidth;
  c.height = kHeight;
  return c;
}

inline CameraIntrinsics radTanCamera() {
  CameraIntrinsics c = pinholeCamera();
  c.model = CameraModelType::RadTan;
  c.distortion = {-0.28, 0.09, 0.0012, -0.0009};
  return c;
}

inline CameraIntrinsics equidistantCamera() {
  CameraIntrinsics c = pinholeCamera();
  c.model = CameraModelType::Equidistant;
  c.fx = 150.0;
  c.fy = 149.0;
  c.distortion = {0.04, -0.012, 0.003, -0.0006};
  return c;
}

/// A chessboard of 9 x 6 squares of 3 cm, or a ChArUco board of 7 x 5 squares of 4 cm (markers
/// need more pixels than chessboard squares at this image size).
inline calib::BoardSpec boardSpec(calib::BoardType type) {
  calib::BoardSpec spec;
  spec.type = type;
  const bool charuco = type == calib::BoardType::Charuco;
  spec.cols = charuco ? 7 : 9;
  spec.rows = charuco ? 5 : 6;
  spec.square_m = charuco ? 0.04 : 0.03;
  spec.marker_m = 0.03;
  spec.dictionary = "DICT_4X4_50";
  return spec;
}

inline drivers::sim::CalibrationTarget targetFor(const calib::BoardSpec& spec) {
  drivers::sim::CalibrationTarget t;
  t.cols = spec.cols;
  t.rows = spec.rows;
  t.square_m = spec.square_m;
  t.margin_m = 0.5 * spec.square_m;
  if (spec.type == calib::BoardType::Charuco) t.texture = calib::drawBoard(spec, 40, 20);
  return t;
}

/// Camera poses looking at the board from different directions and distances (see
/// drivers::sim::calibrationPoses).
inline std::vector<Pose> boardPoses(const drivers::sim::CalibrationTarget& t,
                                    const CameraModel& camera, int count, double distance) {
  return drivers::sim::calibrationPoses(t, camera, count, distance);
}

/// Renders one view of the target and detects the board in it.
inline calib::BoardView renderView(const calib::BoardSpec& spec,
                                   const drivers::sim::CalibrationTarget& target,
                                   const CameraModel& camera, const Pose& pose, int index,
                                   double blur_sigma = 0.0, ImageU8* image_out = nullptr) {
  drivers::sim::TargetRenderOptions o;
  o.noise_sigma = 1.0;
  o.noise_key = static_cast<std::uint32_t>(index + 1);
  o.blur_sigma_px = blur_sigma;
  ImageU8 image;
  drivers::sim::renderTargetView(target, camera, pose, o, image);
  calib::BoardView view;
  view.name = "view" + std::to_string(index) + ".png";
  view.observation = calib::detectBoard(spec, image.view());
  if (image_out) *image_out = std::move(image);
  return view;
}

}  // namespace ldsm::test
