#include "ldsm/calib/calibration_loader.h"

#include <gtest/gtest.h>

#include "calib_test_util.h"
#include "ldsm/calib/describe_calibration.h"
#include "ldsm/calib/dso_camera_file.h"

namespace ldsm::calib {
namespace {

using test::expectInputError;
using test::writeFile;

TEST(CalibrationLoader, DetectsTheFormat) {
  EXPECT_EQ(detectCalibrationFormat("RadTan 1 2 3 4 5 6 7 8\n752 480\ncrop\n640 480\n"),
            CalibrationFormat::DsoCamera);
  EXPECT_EQ(detectCalibrationFormat("0.5 0.6 0.5 0.5 0.9\n752 480\ncrop\n640 480\n"),
            CalibrationFormat::DsoCamera);
  EXPECT_EQ(detectCalibrationFormat("%YAML:1.0\nsensor_type: camera\n"),
            CalibrationFormat::KalibrYaml);
  EXPECT_EQ(detectCalibrationFormat("cam0:\n  camera_model: pinhole\n"),
            CalibrationFormat::KalibrYaml);
  EXPECT_EQ(detectCalibrationFormat("P0: 1 0 2 0 0 1 2 0 0 0 1 0\n"), CalibrationFormat::Kitti);
}

TEST(CalibrationLoader, LoadsEverySharedCalibration) {
  const std::string data = test::sharedData();
  if (data.empty()) GTEST_SKIP() << "../shared/data absent";
  const auto vamr = loadGeometricCalibration(data + "/vamr_desk_loop/camera.txt");
  EXPECT_DOUBLE_EQ(vamr.input.fx, 420.506712);
  const auto euroc = loadGeometricCalibration(data + "/euroc_v101_static95/mav0/cam0/sensor.yaml");
  EXPECT_DOUBLE_EQ(euroc.input.fx, 458.654);
  EXPECT_EQ(euroc.input.model, CameraModelType::RadTan);
  const auto kitti =
      loadGeometricCalibration(data + "/kitti00_200/sequences/00/calib.txt", 1241, 376);
  EXPECT_DOUBLE_EQ(kitti.input.fx, 718.856);
  EXPECT_EQ(kitti.input.width, 1241);
  // KITTI without the image size is an error naming the file.
  const std::string kitti_path = data + "/kitti00_200/sequences/00/calib.txt";
  expectInputError([&] { loadGeometricCalibration(kitti_path); }, kitti_path, 0, "image size");
}

TEST(CalibrationLoader, PassesParserErrorsThrough) {
  const std::string dir = test::scratchDir("calib_loader_errors");
  const std::string p = writeFile(dir, "camera.txt", "Pinhole 1 2 3\n1 2\ncrop\n1 2\n");
  expectInputError([&] { loadGeometricCalibration(p); }, p, 1, "4 numbers");
  expectInputError([&] { loadGeometricCalibration(dir + "/absent"); }, dir + "/absent", 0,
                   "cannot open");
}

TEST(DescribeCalibration, SummarizesInputAndOutput) {
  const auto c = parseDsoCameraFile(
      "RadTan 458.654 457.296 367.215 248.375 -0.28340811 0.07395907 0.00019359 "
      "1.76187114e-05\n752 480\n0.6 0.9 0.5 0.5 0\n640 480\n",
      "mem");
  const std::string text = describe(c);
  EXPECT_NE(text.find("RadTan 752x480"), std::string::npos) << text;
  EXPECT_NE(text.find("fx=458.654"), std::string::npos) << text;
  EXPECT_NE(text.find("k1=-0.283408"), std::string::npos) << text;
  EXPECT_NE(text.find("explicit (relative 0.6 0.9 0.5 0.5) 640x480"), std::string::npos) << text;
  EXPECT_NE(text.find("fx=384 fy=432 cx=319.5 cy=239.5"), std::string::npos) << text;
  // Horizontal field of view of the output: 2 atan(320 / 384) = 79.6 degrees.
  EXPECT_NE(text.find("field of view 79.6"), std::string::npos) << text;
  GeometricCalibration bad = c;
  bad.output.width = 0;
  EXPECT_NE(describe(bad).find("invalid"), std::string::npos);
  PhotometricCalibration p;
  EXPECT_NE(describe(p).find("vignette none"), std::string::npos);
}

}  // namespace
}  // namespace ldsm::calib
