#include "ldsm/calib/dso_camera_file.h"

#include <gtest/gtest.h>

#include "calib_test_util.h"
#include "ldsm/camera/rectifier.h"

namespace ldsm::calib {
namespace {

using test::expectInputError;
using test::writeFile;

TEST(DsoCameraFile, ReadsTheVamrCamera) {
  const std::string path = test::sharedData("vamr_desk_loop/camera.txt");
  if (path.empty()) GTEST_SKIP() << "../shared/data absent: vamr_desk_loop/camera.txt";
  const GeometricCalibration c = readDsoCameraFile(path);
  EXPECT_EQ(c.input.model, CameraModelType::RadTan);
  EXPECT_DOUBLE_EQ(c.input.fx, 420.506712);
  EXPECT_DOUBLE_EQ(c.input.fy, 420.61094);
  EXPECT_DOUBLE_EQ(c.input.cx, 355.208298);
  EXPECT_DOUBLE_EQ(c.input.cy, 250.336787);
  ASSERT_EQ(c.input.distortion.size(), 4u);
  EXPECT_DOUBLE_EQ(c.input.distortion[0], -0.296681274);
  EXPECT_DOUBLE_EQ(c.input.distortion[1], 0.080856909);
  EXPECT_EQ(c.input.distortion[2], 0.0);
  EXPECT_EQ(c.input.width, 752);
  EXPECT_EQ(c.input.height, 480);
  EXPECT_EQ(c.output.mode, OutputMode::Explicit);
  EXPECT_TRUE(c.output.relative);
  EXPECT_DOUBLE_EQ(c.output.fx, 0.6);
  EXPECT_DOUBLE_EQ(c.output.fy, 0.9);
  EXPECT_EQ(c.output.width, 640);
  EXPECT_EQ(c.output.height, 480);
  const Rectifier rect(c);
  EXPECT_DOUBLE_EQ(rect.output().fx, 384.0);
  EXPECT_DOUBLE_EQ(rect.output().cy, 239.5);
}

TEST(DsoCameraFile, ReadsTheEurocCamera) {
  const std::string path = test::sharedData("euroc_v101_static95/camera.txt");
  if (path.empty()) GTEST_SKIP() << "../shared/data absent: euroc_v101_static95/camera.txt";
  const GeometricCalibration c = readDsoCameraFile(path);
  EXPECT_EQ(c.input.model, CameraModelType::RadTan);
  EXPECT_DOUBLE_EQ(c.input.fx, 458.654);
  EXPECT_DOUBLE_EQ(c.input.cy, 248.375);
  EXPECT_DOUBLE_EQ(c.input.distortion[3], 1.76187114e-05);
  EXPECT_EQ(c.output.mode, OutputMode::Explicit);
  EXPECT_EQ(c.output.width, 640);
}

TEST(DsoCameraFile, ReadsTheKittiCamera) {
  const std::string path = test::sharedData("kitti00_200/camera.txt");
  if (path.empty()) GTEST_SKIP() << "../shared/data absent: kitti00_200/camera.txt";
  const GeometricCalibration c = readDsoCameraFile(path);
  EXPECT_EQ(c.input.model, CameraModelType::Pinhole);
  EXPECT_TRUE(c.input.distortion.empty());
  EXPECT_DOUBLE_EQ(c.input.fx, 718.856);
  EXPECT_DOUBLE_EQ(c.input.cx, 607.1928);
  EXPECT_DOUBLE_EQ(c.input.cy, 185.2157);
  EXPECT_EQ(c.input.width, 1241);
  EXPECT_EQ(c.input.height, 376);
  EXPECT_EQ(c.output.mode, OutputMode::Crop);
  EXPECT_EQ(c.output.width, 1232);
  EXPECT_EQ(c.output.height, 368);
  // Cropping an undistorted pinhole keeps the whole image: every output pixel valid and the
  // focal length scaled by the ratio of the pixel-center spans.
  const Rectifier rect(c);
  EXPECT_EQ(rect.numValidPixels(), 1232 * 368);
  EXPECT_NEAR(rect.output().fx, 718.856 * 1231.0 / 1240.0, 0.5);
  EXPECT_NEAR(rect.output().fy, 718.856 * 367.0 / 375.0, 0.5);
}

TEST(DsoCameraFile, ParsesEveryModelAndOutputMode) {
  auto c = parseDsoCameraFile(
      "EquiDistant 190 191 254 256 0.01 0.02 -0.03 0.004\n512 512\nfull\n"
      "400 400\n",
      "mem");
  EXPECT_EQ(c.input.model, CameraModelType::Equidistant);
  EXPECT_EQ(c.input.distortion[3], 0.004);
  EXPECT_EQ(c.output.mode, OutputMode::Full);
  c = parseDsoCameraFile(
      "KannalaBrandt 190 191 254 256 0.01 0.02 -0.03 0.004\n512 512\ncrop\n"
      "512 512\n",
      "mem");
  EXPECT_EQ(c.input.model, CameraModelType::Equidistant);
  EXPECT_EQ(c.output.mode, OutputMode::Crop);
  c = parseDsoCameraFile("FOV 300 310 320 240 0.9\n640 480\nFull\n600 400\n", "mem");
  EXPECT_EQ(c.input.model, CameraModelType::Fov);
  EXPECT_EQ(c.input.distortion[0], 0.9);
  EXPECT_EQ(c.output.mode, OutputMode::Full);
  c = parseDsoCameraFile("Pinhole 300 310 320 240 0\n640 480\nnone\n320 240\n", "mem");
  EXPECT_EQ(c.output.mode, OutputMode::None);
  EXPECT_EQ(c.output.width, 320);
  c = parseDsoCameraFile("pinhole 300 310 320 240\n640 480\n300 300 320 240 0\n640 480\n", "mem");
  EXPECT_EQ(c.input.model, CameraModelType::Pinhole);
  EXPECT_EQ(c.output.mode, OutputMode::Explicit);
  EXPECT_FALSE(c.output.relative);
  EXPECT_EQ(c.output.cx, 320);
}

TEST(DsoCameraFile, OldStyleAndRelativeIntrinsics) {
  // TUM-Mono style: 5 numbers, all relative, FOV.
  auto c = parseDsoCameraFile(
      "# TUM-Mono\n0.535719308086809 0.669566858850269 0.493248545285398 0.500408664348414 "
      "0.897966326944875\n1280 1024\n0.4 0.53 0.5 0.5 0\n640 480\n",
      "mem");
  EXPECT_EQ(c.input.model, CameraModelType::Fov);
  EXPECT_DOUBLE_EQ(c.input.fx, 0.535719308086809 * 1280);
  EXPECT_DOUBLE_EQ(c.input.fy, 0.669566858850269 * 1024);
  EXPECT_DOUBLE_EQ(c.input.cx, 0.493248545285398 * 1280 - 0.5);
  EXPECT_DOUBLE_EQ(c.input.cy, 0.500408664348414 * 1024 - 0.5);
  EXPECT_DOUBLE_EQ(c.input.distortion[0], 0.897966326944875);
  EXPECT_TRUE(c.output.relative);
  // Omega 0: a pinhole.
  c = parseDsoCameraFile("300 310 320 240 0\n640 480\nnone\n640 480\n", "mem");
  EXPECT_EQ(c.input.model, CameraModelType::Pinhole);
  EXPECT_TRUE(c.input.distortion.empty());
}

void expectRoundTrip(const GeometricCalibration& c, const std::string& dir) {
  const std::string path = dir + "/camera.txt";
  writeDsoCameraFile(path, c);
  const GeometricCalibration r = readDsoCameraFile(path);
  EXPECT_EQ(r.input.model, c.input.model);
  EXPECT_EQ(r.input.fx, c.input.fx);
  EXPECT_EQ(r.input.fy, c.input.fy);
  EXPECT_EQ(r.input.cx, c.input.cx);
  EXPECT_EQ(r.input.cy, c.input.cy);
  EXPECT_EQ(r.input.distortion, c.input.distortion);
  EXPECT_EQ(r.input.width, c.input.width);
  EXPECT_EQ(r.input.height, c.input.height);
  EXPECT_EQ(r.output.mode, c.output.mode);
  EXPECT_EQ(r.output.width, c.output.width);
  EXPECT_EQ(r.output.height, c.output.height);
  if (c.output.mode == OutputMode::Explicit) {
    EXPECT_EQ(r.output.relative, c.output.relative);
    EXPECT_EQ(r.output.fx, c.output.fx);
    EXPECT_EQ(r.output.fy, c.output.fy);
    EXPECT_EQ(r.output.cx, c.output.cx);
    EXPECT_EQ(r.output.cy, c.output.cy);
  }
}

TEST(DsoCameraFile, WriteReadRoundTrip) {
  const std::string dir = test::scratchDir("calib_dso_roundtrip");
  GeometricCalibration c;
  c.input = {CameraModelType::RadTan,
             458.654,
             457.296,
             367.215,
             248.375,
             {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05},
             752,
             480};
  c.output = {OutputMode::Explicit, 0.6, 0.9, 0.5, 0.5, true, 640, 480};
  expectRoundTrip(c, dir);
  c.output = {OutputMode::Explicit, 384.25, 432.125, 319.5, 239.5, false, 640, 480};
  expectRoundTrip(c, dir);
  c.output = {OutputMode::Crop, 0, 0, 0, 0, false, 752, 480};
  expectRoundTrip(c, dir);
  c.input = {CameraModelType::Equidistant,         190.1 / 3, 191.7, 254.9, 256.9,
             {0.0034, 0.0007, -0.0021, 1.0 / 3.0}, 512,       512};
  c.output = {OutputMode::Full, 0, 0, 0, 0, false, 500, 400};
  expectRoundTrip(c, dir);
  c.input = {CameraModelType::Fov, 300, 310, 319.5, 239.5, {0.9}, 640, 480};
  expectRoundTrip(c, dir);
  c.input = {CameraModelType::Pinhole, 718.856, 718.856, 607.1928, 185.2157, {}, 1241, 376};
  c.output = {OutputMode::None, 0, 0, 0, 0, false, 1241, 376};
  expectRoundTrip(c, dir);
}

TEST(DsoCameraFile, WritingAnInvalidCalibrationFails) {
  const std::string dir = test::scratchDir("calib_dso_write_invalid");
  GeometricCalibration c;
  c.input = {CameraModelType::Pinhole, -1, 300, 320, 240, {}, 640, 480};
  c.output = {OutputMode::None, 0, 0, 0, 0, false, 640, 480};
  EXPECT_THROW(writeDsoCameraFile(dir + "/camera.txt", c), InputError);
  c.input.fx = 300;
  c.output.width = 0;
  EXPECT_THROW(writeDsoCameraFile(dir + "/camera.txt", c), InputError);
  c.output.width = 640;
  EXPECT_THROW(writeDsoCameraFile(dir + "/no/such/dir/camera.txt", c), Error);
}

struct BadCase {
  std::string text;
  int line;
  std::string message;
};

TEST(DsoCameraFile, BadInputNamesFileLineAndField) {
  const std::string dir = test::scratchDir("calib_dso_bad");
  const std::string good_tail = "752 480\ncrop\n640 480\n";
  const std::vector<BadCase> cases = {
      // wrong number counts
      {"RadTan 458 457 367 248 -0.28 0.07 0.0001\n" + good_tail, 1, "8 numbers"},
      {"Pinhole 458 457 367\n" + good_tail, 1, "4 numbers"},
      {"FOV 458 457 367 248\n" + good_tail, 1, "5 numbers"},
      {"458 457 367 248\n" + good_tail, 1, "5 numbers"},
      {"Pinhole 458 457 367 248 0\n752\ncrop\n640 480\n", 2, "input size"},
      {"Pinhole 458 457 367 248 0\n752 480\ncrop\n640\n", 4, "output size"},
      {"Pinhole 458 457 367 248 0\n752 480\n300 300 320\n640 480\n", 3, "5 numbers"},
      // NaN / inf / garbage
      {"RadTan 458 nan 367 248 -0.28 0.07 0.0001 0.0\n" + good_tail, 1, "fy is not finite"},
      {"RadTan 458 457 367 248 -0.28 inf 0.0001 0.0\n" + good_tail, 1, "k2 is not finite"},
      {"RadTan 458 457 3x7 248 -0.28 0.07 0.0001 0.0\n" + good_tail, 1, "cx"},
      {"Pinhole 458 457 367 248 0\n752 480\n300 nan 320 240 0\n640 480\n", 3, "output fy"},
      // negative or zero focal length
      {"Pinhole -458 457 367 248 0\n" + good_tail, 1, "fx must be positive"},
      {"Pinhole 458 0 367 248 0\n" + good_tail, 1, "fy must be positive"},
      {"Pinhole 458 457 367 248 0\n752 480\n0 300 320 240 0\n640 480\n", 3,
       "output fx must be positive"},
      // non-positive or non-integer sizes
      {"Pinhole 458 457 367 248 0\n0 480\ncrop\n640 480\n", 2, "input width"},
      {"Pinhole 458 457 367 248 0\n752 -480\ncrop\n640 480\n", 2, "input height"},
      {"Pinhole 458 457 367 248 0\n752 480\ncrop\n640.5 480\n", 4, "output width"},
      // unknown keywords
      {"Pinhole 458 457 367 248 0\n752 480\ncropped\n640 480\n", 3, "unknown output mode"},
      {"Fisheye 458 457 367 248 0\n" + good_tail, 1, "unknown camera model 'Fisheye'"},
      // output larger than input for crop / full
      {"Pinhole 458 457 367 248 0\n752 480\ncrop\n800 480\n", 4, "larger than the input"},
      {"Pinhole 458 457 367 248 0\n752 480\nfull\n752 481\n", 4, "larger than the input"},
      // semantic errors
      {"RadTan 458 457 367 248 -0.28 0.07 0.0001 0.0\n752 480\nnone\n752 480\n", 3, "none"},
      {"Pinhole 458 457 367 248 0.3\n" + good_tail, 1, "5th value must be 0"},
      {"FOV 458 457 367 248 4.0\n" + good_tail, 1, "omega"},
      {"Pinhole 458 457 367 248 0\n752 480\n300 300 320 240 1\n640 480\n", 3, "must be 0"},
      // missing and extra lines (comments and blank lines keep the real line numbers)
      {"# comment\nPinhole 458 457 367 248 0\n\n752 480\n", 5, "missing line 3"},
      {"", 1, "missing line 1"},
      {"Pinhole 458 457 367 248 0\n752 480\ncrop\n640 480\n\nextra\n", 6, "unexpected content"},
  };
  int i = 0;
  for (const auto& c : cases) {
    const std::string path = writeFile(dir, "camera" + std::to_string(i++) + ".txt", c.text);
    SCOPED_TRACE(c.text);
    expectInputError([&] { readDsoCameraFile(path); }, path, c.line, c.message);
  }
  expectInputError([&] { readDsoCameraFile(dir + "/missing.txt"); }, dir + "/missing.txt", 0,
                   "cannot open");
}

}  // namespace
}  // namespace ldsm::calib
