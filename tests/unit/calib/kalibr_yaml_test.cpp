#include "ldsm/calib/kalibr_yaml.h"

#include <gtest/gtest.h>

#include "calib_test_util.h"
#include "ldsm/camera/rectifier.h"

namespace ldsm::calib {
namespace {

using test::expectInputError;
using test::writeFile;

TEST(KalibrYaml, ReadsTheEurocSensorYaml) {
  const std::string path = test::sharedData("euroc_v101_static95/mav0/cam0/sensor.yaml");
  if (path.empty()) GTEST_SKIP() << "../shared/data absent: euroc_v101_static95 sensor.yaml";
  const GeometricCalibration c = readKalibrCameraYaml(path);
  EXPECT_EQ(c.input.model, CameraModelType::RadTan);
  EXPECT_DOUBLE_EQ(c.input.fx, 458.654);
  EXPECT_DOUBLE_EQ(c.input.fy, 457.296);
  EXPECT_DOUBLE_EQ(c.input.cx, 367.215);
  EXPECT_DOUBLE_EQ(c.input.cy, 248.375);
  ASSERT_EQ(c.input.distortion.size(), 4u);
  EXPECT_DOUBLE_EQ(c.input.distortion[0], -0.28340811);
  EXPECT_DOUBLE_EQ(c.input.distortion[1], 0.07395907);
  EXPECT_DOUBLE_EQ(c.input.distortion[2], 0.00019359);
  EXPECT_DOUBLE_EQ(c.input.distortion[3], 1.76187114e-05);
  EXPECT_EQ(c.input.width, 752);
  EXPECT_EQ(c.input.height, 480);
  // Default output: crop at the input size.
  EXPECT_EQ(c.output.mode, OutputMode::Crop);
  EXPECT_EQ(c.output.width, 752);
  EXPECT_EQ(c.output.height, 480);
  const Rectifier rect(c);
  EXPECT_EQ(rect.numValidPixels(), 752 * 480);
}

constexpr const char* kCamchain = R"(cam0:
  cam_overlaps: [1]
  camera_model: pinhole
  distortion_coeffs: [-0.0376, 0.0085, -0.0056, 0.0010]
  distortion_model: equidistant
  intrinsics: [190.97, 190.97, 254.93, 256.90]
  resolution: [512, 512]
  rostopic: /cam0/image_raw
cam1:
  T_cn_cnm1:
  - [1.0, 0.0, 0.0, -0.1]
  - [0.0, 1.0, 0.0, 0.0]
  - [0.0, 0.0, 1.0, 0.0]
  - [0.0, 0.0, 0.0, 1.0]
  camera_model: pinhole
  distortion_coeffs: [0.92]
  distortion_model: fov
  intrinsics: [300.0, 301.0, 320.0, 240.0]
  resolution: [640, 480]
)";

TEST(KalibrYaml, ReadsAKalibrCamchain) {
  const std::string dir = test::scratchDir("calib_kalibr_camchain");
  const std::string path = writeFile(dir, "camchain.yaml", kCamchain);
  GeometricCalibration c = readKalibrCameraYaml(path);
  EXPECT_EQ(c.input.model, CameraModelType::Equidistant);
  EXPECT_DOUBLE_EQ(c.input.fx, 190.97);
  EXPECT_DOUBLE_EQ(c.input.cy, 256.90);
  EXPECT_DOUBLE_EQ(c.input.distortion[2], -0.0056);
  EXPECT_EQ(c.input.width, 512);
  c = readKalibrCameraYaml(path, "cam1");
  EXPECT_EQ(c.input.model, CameraModelType::Fov);
  EXPECT_DOUBLE_EQ(c.input.distortion[0], 0.92);
  EXPECT_DOUBLE_EQ(c.input.fy, 301.0);
  EXPECT_EQ(c.input.height, 480);
  EXPECT_EQ(c.output.mode, OutputMode::Crop);
}

TEST(KalibrYaml, UndistortedCameraGetsOutputNone) {
  const auto c = parseKalibrCameraYaml(
      "camera_model: pinhole\nintrinsics: [300, 300, 320, 240]\ndistortion_model: radtan\n"
      "distortion_coeffs: [0, 0, 0, 0]\nresolution: [640, 480]\n",
      "mem");
  EXPECT_EQ(c.output.mode, OutputMode::None);
  const auto d = parseKalibrCameraYaml(
      "camera_model: pinhole\nintrinsics: [300, 300, 320, 240]\nresolution: [640, 480]\n", "mem");
  EXPECT_EQ(d.input.model, CameraModelType::Pinhole);
  EXPECT_EQ(d.output.mode, OutputMode::None);
}

struct BadCase {
  std::string text;
  int line;
  std::string message;
};

TEST(KalibrYaml, BadInputNamesFileLineAndField) {
  const std::string dir = test::scratchDir("calib_kalibr_bad");
  const std::string model = "camera_model: pinhole\n";
  const std::string intr = "intrinsics: [458.654, 457.296, 367.215, 248.375]\n";
  const std::string dist =
      "distortion_model: radial-tangential\ndistortion_coefficients: [-0.28, 0.07, 0.0002, 0.0]\n";
  const std::string res = "resolution: [752, 480]\n";
  const std::vector<BadCase> cases = {
      {"%YAML:1.0\n" + model + "intrinsics: [458.654, 457.296, 367.215]\n" + dist + res, 3,
       "needs 4 numbers"},
      {model + "intrinsics: [458.654, .nan, 367.215, 248.375]\n" + dist + res, 2, "intrinsics fv"},
      {model + "intrinsics: [-458.654, 457.296, 367.215, 248.375]\n" + dist + res, 2,
       "fu must be positive"},
      {model + intr + dist + "resolution: [752, 0]\n", 5, "resolution height"},
      {model + intr + dist + "resolution: 752\n", 5, "resolution"},
      {model + intr + "distortion_model: radtan\ndistortion_coeffs: [-0.28, 0.07]\n" + res, 4,
       "needs 4 numbers"},
      {model + intr + "distortion_model: radtan\ndistortion_coeffs: [-0.28, 0.07, inf, 0]\n" + res,
       4, "distortion_coeffs p1 is not finite"},
      {model + intr + "distortion_model: mystery\n" + res, 3, "distortion_model 'mystery'"},
      {"camera_model: omni\n" + intr + dist + res, 1, "camera_model 'omni'"},
      {model + intr + dist, 1, "missing key 'resolution'"},
      {model + dist + res, 1, "missing key 'intrinsics'"},
      {model + intr + "  bad: [\n" + res, 3, "YAML"},
  };
  int i = 0;
  for (const auto& c : cases) {
    const std::string path = writeFile(dir, "sensor" + std::to_string(i++) + ".yaml", c.text);
    SCOPED_TRACE(c.text);
    expectInputError([&] { readKalibrCameraYaml(path); }, path, c.line, c.message);
  }
  const std::string chain = writeFile(dir, "camchain.yaml", kCamchain);
  expectInputError([&] { readKalibrCameraYaml(chain, "cam7"); }, chain, 0, "'cam7'");
  expectInputError([&] { readKalibrCameraYaml(dir + "/none.yaml"); }, dir + "/none.yaml", 0,
                   "cannot open");
}

}  // namespace
}  // namespace ldsm::calib
