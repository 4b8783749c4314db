#include "pipeline/frame_preprocessor.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "ldsm/camera/photometric_model.h"
#include "ldsm/camera/rectifier.h"
#include "ldsm/error.h"

namespace ldsm {
namespace {

constexpr int kW = 32;
constexpr int kH = 24;

GeometricCalibration identityPinhole() {
  GeometricCalibration c;
  c.input.model = CameraModelType::Pinhole;
  c.input.fx = c.input.fy = 30.0;
  c.input.cx = 15.5;
  c.input.cy = 11.5;
  c.input.width = kW;
  c.input.height = kH;
  c.output.mode = OutputMode::None;
  c.output.width = kW;
  c.output.height = kH;
  return c;
}

/// A raw frame: a ramp with one row of values 240..255 in steps of 1.
std::vector<std::uint8_t> rawFrame() {
  std::vector<std::uint8_t> px(kW * kH);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) px[y * kW + x] = static_cast<std::uint8_t>(4 * x + y);
  for (int x = 0; x < 16; ++x) px[10 * kW + x] = static_cast<std::uint8_t>(240 + x);
  return px;
}

// Saturation is a property of the raw value: with a response calibration the corrected value of
// a clipped pixel can lie anywhere, and the mask must still come from the raw one.
TEST(FramePreprocessor, MarksClippedPixelsFromRawValues) {
  PhotometricCalibration gamma;
  gamma.has_response = true;
  for (int v = 0; v < 256; ++v)
    gamma.inverse_response[v] = static_cast<float>(255.0 * std::pow(v / 255.0, 3.0));
  const std::vector<std::uint8_t> raw = rawFrame();
  const ImageView<const std::uint8_t> view(raw.data(), kW, kH, kW);
  for (const bool with_response : {false, true}) {
    PhotometricConfig config;
    config.clipped_level = 250.0;
    FramePreprocessor pre(identityPinhole(), with_response ? gamma : PhotometricCalibration{},
                          config);
    ImagePyramid pyr(kW, kH, 2);
    pre.process(view, pyr);
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x)
        EXPECT_EQ(pyr.clipped()(x, y), raw[y * kW + x] >= 250 ? 1 : 0)
            << x << ", " << y << (with_response ? " (with response)" : "");
    if (with_response) {  // the corrected value of raw 250 is far below 250
      EXPECT_LT(pyr.gradients(0)(10, 10).intensity, 245.f);
      EXPECT_EQ(pyr.clipped()(10, 10), 1);
    }
  }
}

// The pyramid is built row by row from the rectifier: the same bits as building it from the
// whole rectified image, for a distorted camera with and without a photometric model.
TEST(FramePreprocessor, BuildsThePyramidOfTheRectifiedImage) {
  GeometricCalibration c;
  c.input.model = CameraModelType::RadTan;
  c.input.fx = 40.0;
  c.input.fy = 41.0;
  c.input.cx = 16.2;
  c.input.cy = 11.7;
  c.input.distortion = {-0.2, 0.05, 0.001, -0.002};
  c.input.width = kW;
  c.input.height = kH;
  c.output.mode = OutputMode::Crop;
  c.output.width = 28;
  c.output.height = 20;
  PhotometricCalibration gamma;
  gamma.has_response = true;
  for (int v = 0; v < 256; ++v)
    gamma.inverse_response[v] = static_cast<float>(255.0 * std::pow(v / 255.0, 2.2));
  const std::vector<std::uint8_t> raw = rawFrame();
  const ImageView<const std::uint8_t> view(raw.data(), kW, kH, kW);
  for (const bool with_response : {false, true}) {
    FramePreprocessor pre(c, with_response ? gamma : PhotometricCalibration{}, PhotometricConfig{});
    ImagePyramid pyr(28, 20, 3);
    pre.process(view, pyr);
    const Rectifier rect(c);
    ImageF corrected, rectified;
    if (with_response) {
      PhotometricModel(gamma, kW, kH).correct(view, corrected);
      rect.rectify(corrected.view(), rectified);
    } else {
      rect.rectify(view, rectified);
    }
    ImagePyramid expected(28, 20, 3);
    expected.build(rectified.view());
    for (int l = 0; l < 3; ++l)
      for (int y = 0; y < expected.height(l); ++y)
        for (int x = 0; x < expected.width(l); ++x) {
          const GradientPixel a = pyr.gradients(l)(x, y), b = expected.gradients(l)(x, y);
          ASSERT_EQ(a.intensity, b.intensity) << l << ": " << x << ", " << y;
          ASSERT_EQ(a.dx, b.dx) << l << ": " << x << ", " << y;
          ASSERT_EQ(a.dy, b.dy) << l << ": " << x << ", " << y;
        }
  }
  ImagePyramid wrong(27, 20, 3);
  FramePreprocessor pre(c, PhotometricCalibration{}, PhotometricConfig{});
  EXPECT_THROW(pre.process(view, wrong), InputError);
}

TEST(FramePreprocessor, ClippingCanBeTurnedOff) {
  PhotometricConfig config;
  config.clipped_level = 256.0;
  FramePreprocessor pre(identityPinhole(), PhotometricCalibration{}, config);
  std::vector<std::uint8_t> raw(kW * kH, 255);
  ImagePyramid pyr(kW, kH, 2);
  pre.process(ImageView<const std::uint8_t>(raw.data(), kW, kH, kW), pyr);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) EXPECT_EQ(pyr.clipped()(x, y), 0);
}

}  // namespace
}  // namespace ldsm
