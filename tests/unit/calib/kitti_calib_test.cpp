#include "ldsm/calib/kitti_calib.h"

#include <gtest/gtest.h>

#include "calib_test_util.h"

namespace ldsm::calib {
namespace {

using test::expectInputError;
using test::writeFile;

TEST(KittiCalib, ReadsTheSharedSequence) {
  const std::string path = test::sharedData("kitti00_200/sequences/00/calib.txt");
  if (path.empty()) GTEST_SKIP() << "../shared/data absent: kitti00_200 calib.txt";
  const GeometricCalibration c = readKittiCalib(path, 0, 1241, 376);
  EXPECT_EQ(c.input.model, CameraModelType::Pinhole);
  EXPECT_DOUBLE_EQ(c.input.fx, 718.856);
  EXPECT_DOUBLE_EQ(c.input.fy, 718.856);
  EXPECT_DOUBLE_EQ(c.input.cx, 607.1928);
  EXPECT_DOUBLE_EQ(c.input.cy, 185.2157);
  EXPECT_EQ(c.input.width, 1241);
  EXPECT_EQ(c.input.height, 376);
  EXPECT_EQ(c.output.mode, OutputMode::None);
  EXPECT_EQ(c.output.width, 1241);
}

constexpr const char* kCalib =
    "P0: 7.07e+02 0 6.04e+02 0 0 7.07e+02 1.8e+02 0 0 0 1 0\n"
    "P1: 7.07e+02 0 6.04e+02 -3.79e+02 0 7.07e+02 1.8e+02 0 0 0 1 0\n"
    "P2: 7.1e+02 0 6.1e+02 4.5e+01 0 7.1e+02 1.7e+02 -0.3 0 0 1 0.004\n"
    "Tr: 1 0 0 0 0 1 0 0 0 0 1 0\n";

TEST(KittiCalib, SelectsTheCamera) {
  const std::string dir = test::scratchDir("calib_kitti_select");
  const std::string path = writeFile(dir, "calib.txt", kCalib);
  const auto c = readKittiCalib(path, 2, 1242, 375);
  EXPECT_DOUBLE_EQ(c.input.fx, 710.0);
  EXPECT_DOUBLE_EQ(c.input.cx, 610.0);
  EXPECT_DOUBLE_EQ(c.input.cy, 170.0);
  EXPECT_EQ(c.input.height, 375);
}

TEST(KittiCalib, BadInputNamesFileLineAndField) {
  const std::string dir = test::scratchDir("calib_kitti_bad");
  const std::string p = writeFile(dir, "calib.txt", kCalib);
  expectInputError([&] { readKittiCalib(p, 3, 1241, 376); }, p, 0, "no line 'P3:'");
  expectInputError([&] { readKittiCalib(p, 0, 0, 376); }, p, 0, "image size");
  expectInputError([&] { readKittiCalib(p, -1, 1241, 376); }, p, 0, "camera index");
  const std::string short_line = writeFile(dir, "short.txt", "Tr: 1\nP0: 707 0 604 0 0 707 180\n");
  expectInputError([&] { readKittiCalib(short_line, 0, 1241, 376); }, short_line, 2, "12 numbers");
  const std::string nan = writeFile(dir, "nan.txt", "P0: 707 0 604 0 0 nan 180 0 0 0 1 0\n");
  expectInputError([&] { readKittiCalib(nan, 0, 1241, 376); }, nan, 1, "value 6 is not finite");
  const std::string neg = writeFile(dir, "neg.txt", "\nP0: -707 0 604 0 0 707 180 0 0 0 1 0\n");
  expectInputError([&] { readKittiCalib(neg, 0, 1241, 376); }, neg, 2, "fx");
  const std::string skew = writeFile(dir, "skew.txt", "P0: 707 3 604 0 0 707 180 0 0 0 1 0\n");
  expectInputError([&] { readKittiCalib(skew, 0, 1241, 376); }, skew, 1, "skew");
  const std::string proj = writeFile(dir, "proj.txt", "P0: 707 0 604 0 0 707 180 0 0 0 2 0\n");
  expectInputError([&] { readKittiCalib(proj, 0, 1241, 376); }, proj, 1, "rectified pinhole");
  expectInputError([&] { readKittiCalib(dir + "/nope.txt", 0, 1241, 376); }, dir + "/nope.txt", 0,
                   "cannot open");
}

}  // namespace
}  // namespace ldsm::calib
