#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "ldsm/camera/photometric_model.h"
#include "ldsm/error.h"

namespace ldsm {
namespace {

constexpr int kW = 160, kH = 120;
constexpr double kGamma = 2.2;

/// G^-1(v) = 255 (v / 255)^gamma: a gamma-encoding camera.
double gammaInverseResponse(double v) {
  return 255.0 * std::pow(v / 255.0, kGamma);
}

/// V = 1 - 0.35 (r / r_corner)^2 around an off-center point.
double radialVignette(int x, int y) {
  const double dx = x - 70.0, dy = y - 64.0;
  const double r_max2 = 90.0 * 90.0 + 64.0 * 64.0;
  return 1.0 - 0.35 * (dx * dx + dy * dy) / r_max2;
}

PhotometricCalibration gammaCalibration(bool with_vignette) {
  PhotometricCalibration c;
  c.has_response = true;
  for (int i = 0; i < 256; ++i) c.inverse_response[i] = static_cast<float>(gammaInverseResponse(i));
  if (with_vignette) {
    c.vignette.resize(kW, kH);
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) c.vignette(x, y) = static_cast<float>(radialVignette(x, y));
  }
  return c;
}

TEST(PhotometricModel, CorrectionRecoversTheIrradiance) {
  const PhotometricModel model(gammaCalibration(true), kW, kH);
  const float exposure = 2.5f;
  // A smooth irradiance pattern.
  ImageF irradiance(kW, kH);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      irradiance(x, y) =
          static_cast<float>(8.0 + 40.0 * (1.0 + std::sin(0.07 * x) * std::cos(0.05 * y)));
  ImageU8 pixels;
  model.render(irradiance.view(), pixels, exposure);
  ImageF recovered;
  model.correct(pixels.view(), recovered, exposure);
  double sum_err = 0;
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      // Rendering rounds to the nearest pixel value: the irradiance error is at most half a
      // pixel value times the slope of G^-1, divided by V t.
      const double I = pixels(x, y);
      const double slope = gammaInverseResponse(std::min(255.0, I + 0.5)) -
                           gammaInverseResponse(std::max(0.0, I - 0.5));
      const double bound = slope / (radialVignette(x, y) * exposure) + 1e-4;
      const double err = std::abs(recovered(x, y) - irradiance(x, y));
      ASSERT_LE(err, bound) << "at " << x << "," << y;
      sum_err += err / irradiance(x, y);
    }
  }
  EXPECT_LT(sum_err / (kW * kH), 0.01);
  // And the pixel values are what the gamma camera produces.
  const double expected =
      255.0 * std::pow(exposure * radialVignette(5, 7) * irradiance(5, 7) / 255.0, 1.0 / kGamma);
  EXPECT_NEAR(pixels(5, 7), expected, 0.5 + 1e-3);
}

TEST(PhotometricModel, CorrectionOfEachPixelValueIsExact) {
  const PhotometricModel model(gammaCalibration(true), kW, kH);
  ImageU8 img(kW, kH);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) img(x, y) = static_cast<std::uint8_t>((x + 3 * y) % 256);
  ImageF out;
  model.correct(img.view(), out);
  for (int y = 0; y < kH; y += 7)
    for (int x = 0; x < kW; x += 5)
      EXPECT_NEAR(out(x, y), gammaInverseResponse(img(x, y)) / radialVignette(x, y),
                  1e-4 * (1 + out(x, y)));
}

TEST(PhotometricModel, ResponseInvertsTheInverseResponse) {
  const PhotometricModel model(gammaCalibration(false), kW, kH);
  for (int v = 0; v < 256; ++v)
    EXPECT_NEAR(model.response(model.inverseResponse(static_cast<std::uint8_t>(v))), v, 1e-3);
  EXPECT_EQ(model.response(-5.0f), 0.0f);
  EXPECT_EQ(model.response(1e6f), 255.0f);
  // Between table entries G is linear.
  const float mid = 0.5f * (model.inverseResponse(100) + model.inverseResponse(101));
  EXPECT_NEAR(model.response(mid), 100.5, 1e-3);
}

TEST(PhotometricModel, InverseResponseIsNormalizedLikeDso) {
  PhotometricCalibration scaled = gammaCalibration(false);
  for (auto& g : scaled.inverse_response) g = 3.0f * g + 10.0f;
  const PhotometricModel a(scaled, kW, kH), b(gammaCalibration(false), kW, kH);
  for (int v = 0; v < 256; v += 15)
    EXPECT_NEAR(a.inverseResponse(static_cast<std::uint8_t>(v)),
                b.inverseResponse(static_cast<std::uint8_t>(v)), 1e-3);
  EXPECT_FLOAT_EQ(a.inverseResponse(0), 0.0f);
  EXPECT_FLOAT_EQ(a.inverseResponse(255), 255.0f);
}

TEST(PhotometricModel, WithoutCalibrationItIsTheIdentity) {
  const PhotometricModel model(PhotometricCalibration{}, 4, 3);
  ImageU8 img(4, 3, 200);
  ImageF out;
  model.correct(img.view(), out, 4.0f);
  EXPECT_FLOAT_EQ(out(3, 2), 50.0f);
  EXPECT_FALSE(model.hasVignette());
}

TEST(PhotometricModel, CorrectDoesNotReallocateASizedOutput) {
  const PhotometricModel model(gammaCalibration(true), kW, kH);
  ImageU8 img(kW, kH, 9);
  ImageF out(kW, kH);
  const float* before = out.data();
  model.correct(img.view(), out);
  EXPECT_EQ(out.data(), before);
}

void expectError(const PhotometricCalibration& c, const std::string& text, int w = kW, int h = kH) {
  try {
    PhotometricModel m(c, w, h);
    ADD_FAILURE() << "accepted an invalid photometric calibration (" << text << ")";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
  }
}

TEST(PhotometricModel, ValidationNamesTheFirstBadEntry) {
  auto c = gammaCalibration(true);
  c.inverse_response[17] = c.inverse_response[16] - 0.5f;
  expectError(c, "index 17");
  c = gammaCalibration(true);
  c.inverse_response[200] = std::numeric_limits<float>::quiet_NaN();
  expectError(c, "value 200");
  c = gammaCalibration(true);
  c.inverse_response.fill(3.0f);
  expectError(c, "constant");
  c = gammaCalibration(true);
  c.vignette(12, 34) = 0.0f;
  expectError(c, "(12, 34)");
  c = gammaCalibration(true);
  c.vignette(5, 6) = 1.5f;
  expectError(c, "(5, 6)");
  c = gammaCalibration(true);
  c.vignette(7, 8) = std::numeric_limits<float>::quiet_NaN();
  expectError(c, "(7, 8)");
  expectError(gammaCalibration(true), "160x120", kW + 1, kH);
  expectError(PhotometricCalibration{}, "size", 0, 10);
  // Run-time arguments.
  const PhotometricModel model(gammaCalibration(true), kW, kH);
  ImageU8 img(kW, kH, 1), wrong(kW, kH - 1, 1);
  ImageF out;
  EXPECT_THROW(model.correct(wrong.view(), out), InputError);
  EXPECT_THROW(model.correct(img.view(), out, 0.0f), InputError);
  EXPECT_THROW(model.correct(img.view(), out, std::numeric_limits<float>::infinity()), InputError);
}

}  // namespace
}  // namespace ldsm
