#include "ldsm/calib/vignette_calibration.h"

#include <gtest/gtest.h>

#include <cmath>

#include "ldsm/calib/photometric_files.h"
#include "ldsm/drivers/sim/photometric_sequences.h"
#include "ldsm/error.h"
#include "test_paths.h"

namespace ldsm::calib {
namespace {

namespace sim = drivers::sim;

sim::SimOptions flatOptions(double vignette, sim::SimResponse response) {
  sim::SimOptions o;
  o.width = 160;
  o.height = 120;
  o.vignette = vignette;
  o.response = response;
  o.noise_sigma = 1.0;
  return o;
}

std::vector<ExposedImage> asInput(const sim::ExposedFrames& f) {
  std::vector<ExposedImage> in;
  for (std::size_t i = 0; i < f.images.size(); ++i)
    in.push_back({f.images[i].view(), f.exposures_ms[i], "flat" + std::to_string(i) + ".png"});
  return in;
}

/// RMS and largest difference between two vignettes (both with maximum 1).
std::pair<double, double> vignetteError(const ImageF& got, const ImageF& truth) {
  double s = 0, worst = 0;
  for (int y = 0; y < truth.height(); ++y)
    for (int x = 0; x < truth.width(); ++x) {
      const double d = got(x, y) - truth(x, y);
      s += d * d;
      worst = std::max(worst, std::abs(d));
    }
  return {std::sqrt(s / static_cast<double>(truth.size())), worst};
}

struct Case {
  double vignette;
  sim::SimResponse response;
  double spot;
};

class VignetteRecovery : public ::testing::TestWithParam<Case> {};

// Stated accuracy: RMS error of V below 0.002 (0.2 % of its maximum), largest error below 0.006,
// with 8 images of 160 x 120 pixels and noise sigma 1 grey level, even with a stain on the
// surface (measured: RMS 0.0002 - 0.0006).
TEST_P(VignetteRecovery, MatchesTheTrueVignette) {
  const Case c = GetParam();
  const auto o = flatOptions(c.vignette, c.response);
  const auto f = sim::renderFlatField(o, 0.6, sim::exposureSweepTimes(12, 20, 8), c.spot);
  const auto r = calibrateVignette(asInput(f), f.truth.inverse_response, {}, "flat");
  ASSERT_EQ(r.vignette.width(), o.width);
  const auto [rms, worst] = vignetteError(r.vignette, f.truth.vignette);
  EXPECT_LT(rms, 0.002);
  EXPECT_LT(worst, 0.006);
  EXPECT_EQ(r.images_used, 8);
  // The simulator's vignette is centred on the principal point ((w - 1) / 2, (h - 1) / 2).
  EXPECT_NEAR(r.centre.x(), 79.5, 1.5);
  EXPECT_NEAR(r.centre.y(), 59.5, 1.5);
  EXPECT_NEAR(r.min_value, 1.0 - c.vignette, 0.015);
  EXPECT_LT(r.fit_rms, 0.01);
  if (c.spot > 0) {
    // The stain is in the measured average but not in the fitted vignette.
    const Eigen::Vector2i stain(o.width / 4, o.height / 4);
    EXPECT_NEAR(r.measured(stain.x(), stain.y()),
                (1.0 - c.spot) * f.truth.vignette(stain.x(), stain.y()), 0.02);
    EXPECT_NEAR(r.vignette(stain.x(), stain.y()), f.truth.vignette(stain.x(), stain.y()), 0.006);
    EXPECT_GT(r.outlier_fraction, 0.03);
  }
  float vmax = 0;
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x) vmax = std::max(vmax, r.vignette(x, y));
  EXPECT_FLOAT_EQ(vmax, 1.0f);
}

INSTANTIATE_TEST_SUITE_P(Cases, VignetteRecovery,
                         ::testing::Values(Case{0.3, sim::SimResponse::Gamma, 0.0},
                                           Case{0.6, sim::SimResponse::SCurve, 0.0},
                                           Case{0.3, sim::SimResponse::Linear, 0.4}));

TEST(VignetteCalibration, GivenCentreIsKept) {
  const auto o = flatOptions(0.4, sim::SimResponse::Gamma);
  const auto f = sim::renderFlatField(o, 0.6, sim::exposureSweepTimes(12, 20, 4));
  VignetteCalibrationOptions vo;
  vo.centre = Eigen::Vector2d(79.5, 59.5);
  const auto r = calibrateVignette(asInput(f), f.truth.inverse_response, vo, "flat");
  EXPECT_EQ(r.centre, *vo.centre);
  EXPECT_LT(vignetteError(r.vignette, f.truth.vignette).first, 0.005);
  // The simulator's V = 1 - s (r^2 + r^4) / 2 with r relative to the farthest corner, which is
  // the model's radius: a = b = -s / 2, c = 0.
  EXPECT_NEAR(r.coefficients[0], -0.2, 0.02);
  EXPECT_NEAR(r.coefficients[1], -0.2, 0.04);
  EXPECT_NEAR(r.coefficients[2], 0.0, 0.03);
}

TEST(VignetteCalibration, WrittenFileReadsBack) {
  const auto o = flatOptions(0.3, sim::SimResponse::Gamma);
  const auto f = sim::renderFlatField(o, 0.6, sim::exposureSweepTimes(12, 20, 3));
  const auto r = calibrateVignette(asInput(f), f.truth.inverse_response, {}, "flat");
  const std::string dir = test::scratchDir("calibration_vignette_file");
  writeVignette(dir + "/vignette.png", r.vignette);
  const ImageF back = readVignette(dir + "/vignette.png");
  EXPECT_LT(vignetteError(back, r.vignette).second, 1.0 / 65535);
}

TEST(VignetteCalibration, UnevenLightingIsReported) {
  const auto o = flatOptions(0.3, sim::SimResponse::Gamma);
  auto f = sim::renderFlatField(o, 0.6, sim::exposureSweepTimes(12, 20, 4));
  // Light falling off across the surface: brighten the left side, darken the right.
  for (auto& img : f.images)
    for (int y = 0; y < img.height(); ++y)
      for (int x = 0; x < img.width(); ++x)
        img(x, y) = static_cast<std::uint8_t>(
            std::clamp(img(x, y) * (1.25 - 0.5 * x / img.width()), 0.0, 255.0));
  const auto r = calibrateVignette(asInput(f), f.truth.inverse_response, {}, "flat");
  ASSERT_FALSE(r.warnings.empty());
  bool named = false;
  for (const auto& w : r.warnings) named = named || w.find("evenly") != std::string::npos;
  EXPECT_TRUE(named) << r.warnings.front();
}

void expectInputError(const std::vector<ExposedImage>& in, const std::array<float, 256>& g,
                      const std::string& text) {
  try {
    calibrateVignette(in, g, {}, "flat");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("flat: ", 0), 0u) << what;
    EXPECT_NE(what.find(text), std::string::npos) << what;
  }
}

TEST(VignetteCalibration, BadInput) {
  const auto o = flatOptions(0.3, sim::SimResponse::Gamma);
  const auto f = sim::renderFlatField(o, 0.6, sim::exposureSweepTimes(12, 20, 3));
  const auto& g = f.truth.inverse_response;
  expectInputError({}, g, "no images");
  // Saturated: far too long an exposure.
  const auto bright = sim::renderFlatField(o, 0.6, {200, 300});
  expectInputError(asInput(bright), g, "saturated");
  const auto dark = sim::renderFlatField(o, 0.6, {0.0005, 0.001});
  expectInputError(asInput(dark), g, "too dark");
  auto in = asInput(f);
  in[1].exposure_ms = 0;
  expectInputError(in, g, "flat1.png has exposure time");
  in = asInput(f);
  ImageU8 small(8, 8, 100);
  in[2].image = small.view();
  expectInputError(in, g, "flat2.png is 8x8");
  auto decreasing = g;
  decreasing[100] = decreasing[99] - 1;
  expectInputError(asInput(f), decreasing, "non-decreasing at 100");
}

}  // namespace
}  // namespace ldsm::calib
