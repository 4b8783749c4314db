#include "ldsm/calib/photometric_files.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "calib_test_util.h"
#include "ldsm/camera/photometric_model.h"

namespace ldsm::calib {
namespace {

using test::expectInputError;
using test::writeFile;

std::array<float, 256> gammaResponse() {
  std::array<float, 256> g{};
  for (int i = 0; i < 256; ++i) g[i] = static_cast<float>(255.0 * std::pow(i / 255.0, 2.2));
  return g;
}

ImageF radialVignette(int w, int h) {
  ImageF v(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double dx = x - w / 2.0, dy = y - h / 2.0;
      v(x, y) = static_cast<float>(1.0 - 0.5 * (dx * dx + dy * dy) / (w * w / 4.0 + h * h / 4.0));
    }
  return v;
}

TEST(PhotometricFiles, InverseResponseRoundTrip) {
  const std::string dir = test::scratchDir("calib_pcalib_roundtrip");
  const auto g = gammaResponse();
  writeInverseResponse(dir + "/pcalib.txt", g);
  EXPECT_EQ(readInverseResponse(dir + "/pcalib.txt"), g);
}

TEST(PhotometricFiles, InverseResponseAcrossSeveralLines) {
  const std::string dir = test::scratchDir("calib_pcalib_lines");
  std::string text = "# G^-1\n";
  for (int i = 0; i < 256; ++i) text += std::to_string(i * 2) + ((i % 16 == 15) ? "\n" : " ");
  const auto g = readInverseResponse(writeFile(dir, "pcalib.txt", text));
  EXPECT_EQ(g[0], 0.0f);
  EXPECT_EQ(g[100], 200.0f);
  EXPECT_EQ(g[255], 510.0f);
}

TEST(PhotometricFiles, BadInverseResponse) {
  const std::string dir = test::scratchDir("calib_pcalib_bad");
  std::string values;
  for (int i = 0; i < 255; ++i) values += std::to_string(i) + " ";
  // 255 values
  std::string p = writeFile(dir, "short.txt", values + "\n");
  expectInputError([&] { readInverseResponse(p); }, p, 1, "found 255");
  // 257 values on line 2
  p = writeFile(dir, "long.txt", values + "255\n256\n");
  expectInputError([&] { readInverseResponse(p); }, p, 2, "more than 256");
  // decreasing at index 17 (line 2)
  std::string dec;
  for (int i = 0; i < 256; ++i) dec += std::to_string(i == 17 ? 3 : i) + (i == 9 ? "\n" : " ");
  p = writeFile(dir, "dec.txt", dec);
  expectInputError([&] { readInverseResponse(p); }, p, 2, "index 17");
  // NaN at index 5
  std::string bad;
  for (int i = 0; i < 256; ++i) bad += (i == 5 ? std::string("nan") : std::to_string(i)) + " ";
  p = writeFile(dir, "nan.txt", bad);
  expectInputError([&] { readInverseResponse(p); }, p, 1, "value 5 is not finite");
  // garbage
  p = writeFile(dir, "text.txt", "0 1 two\n");
  expectInputError([&] { readInverseResponse(p); }, p, 1, "'two' is not a number");
  // constant
  std::string flat;
  for (int i = 0; i < 256; ++i) flat += "7 ";
  p = writeFile(dir, "flat.txt", flat);
  expectInputError([&] { readInverseResponse(p); }, p, 1, "constant");
  expectInputError([&] { readInverseResponse(dir + "/absent.txt"); }, dir + "/absent.txt", 0,
                   "cannot open");
}

TEST(PhotometricFiles, VignetteRoundTripIn16Bit) {
  const std::string dir = test::scratchDir("calib_vignette_roundtrip");
  const ImageF v = radialVignette(64, 48);
  writeVignette(dir + "/vignette.png", v);
  const cv::Mat raw = cv::imread(dir + "/vignette.png", cv::IMREAD_UNCHANGED);
  EXPECT_EQ(raw.depth(), CV_16U);
  const ImageF r = readVignette(dir + "/vignette.png");
  ASSERT_EQ(r.width(), 64);
  ASSERT_EQ(r.height(), 48);
  float max_value = 0;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) {
      EXPECT_NEAR(r(x, y), v(x, y), 1.0 / 65535);
      max_value = std::max(max_value, r(x, y));
    }
  EXPECT_EQ(max_value, 1.0f);
}

TEST(PhotometricFiles, EightBitVignetteIsScaledToMaximumOne) {
  const std::string dir = test::scratchDir("calib_vignette_8bit");
  cv::Mat img(10, 20, CV_8UC1, cv::Scalar(100));
  img.at<std::uint8_t>(3, 4) = 200;
  cv::imwrite(dir + "/v.png", img);
  const ImageF v = readVignette(dir + "/v.png");
  EXPECT_FLOAT_EQ(v(4, 3), 1.0f);
  EXPECT_FLOAT_EQ(v(0, 0), 0.5f);
}

TEST(PhotometricFiles, BadVignette) {
  const std::string dir = test::scratchDir("calib_vignette_bad");
  cv::Mat zero(10, 20, CV_16UC1, cv::Scalar(1000));
  zero.at<std::uint16_t>(7, 12) = 0;
  cv::imwrite(dir + "/zero.png", zero);
  expectInputError([&] { readVignette(dir + "/zero.png"); }, dir + "/zero.png", 0, "(12, 7)");
  cv::imwrite(dir + "/color.png", cv::Mat(10, 20, CV_8UC3, cv::Scalar(1, 2, 3)));
  expectInputError([&] { readVignette(dir + "/color.png"); }, dir + "/color.png", 0,
                   "single-channel");
  const std::string junk = writeFile(dir, "junk.png", "not a png");
  expectInputError([&] { readVignette(junk); }, junk, 0, "cannot decode");
  expectInputError([&] { readVignette(dir + "/absent.png"); }, dir + "/absent.png", 0,
                   "cannot open");
  ImageF bad = radialVignette(8, 8);
  bad(2, 3) = std::nanf("");
  EXPECT_THROW(writeVignette(dir + "/w.png", bad), InputError);
  EXPECT_THROW(writeVignette(dir + "/w.png", ImageF()), InputError);
}

TEST(PhotometricFiles, LoadPhotometricCalibration) {
  const std::string dir = test::scratchDir("calib_photometric_load");
  writeInverseResponse(dir + "/pcalib.txt", gammaResponse());
  writeVignette(dir + "/vignette.png", radialVignette(32, 24));
  const auto c = loadPhotometricCalibration(dir + "/pcalib.txt", dir + "/vignette.png", 32, 24);
  EXPECT_TRUE(c.has_response);
  EXPECT_EQ(c.inverse_response[128], gammaResponse()[128]);
  EXPECT_EQ(c.vignette.width(), 32);
  const PhotometricModel model(c, 32, 24);
  EXPECT_TRUE(model.hasVignette());
  const auto only_response = loadPhotometricCalibration(dir + "/pcalib.txt", "", 32, 24);
  EXPECT_TRUE(only_response.vignette.empty());
  const auto nothing = loadPhotometricCalibration("", "", 32, 24);
  EXPECT_FALSE(nothing.has_response);
  expectInputError(
      [&] { loadPhotometricCalibration(dir + "/pcalib.txt", dir + "/vignette.png", 640, 480); },
      dir + "/vignette.png", 0, "32x24 but the images are 640x480");
}

}  // namespace
}  // namespace ldsm::calib
