#include "ldsm/calib/response_calibration.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "ldsm/drivers/sim/photometric_sequences.h"
#include "ldsm/error.h"

namespace ldsm::calib {
namespace {

namespace sim = drivers::sim;

sim::SimOptions sweepOptions(sim::SimResponse response, double noise = 1.0) {
  sim::SimOptions o;
  o.width = 160;
  o.height = 120;
  o.response = response;
  o.noise_sigma = noise;
  o.vignette = 0.3;
  return o;
}

/// Exposure sweeps are rendered once per response curve and noise (a scene takes a while to
/// build).
const sim::ExposedFrames& sweep(sim::SimResponse response, double noise = 1.0) {
  static std::map<std::pair<sim::SimResponse, double>, sim::ExposedFrames> cache;
  const auto key = std::make_pair(response, noise);
  auto it = cache.find(key);
  if (it == cache.end())
    it = cache
             .emplace(key, sim::renderExposureSweep("loop", sweepOptions(response, noise),
                                                    sim::exposureSweepTimes(0.05, 400, 40)))
             .first;
  return it->second;
}

std::vector<ExposedImage> asInput(const sim::ExposedFrames& f,
                                  const std::vector<double>& exposures = {}) {
  std::vector<ExposedImage> in;
  for (std::size_t i = 0; i < f.images.size(); ++i)
    in.push_back({f.images[i].view(), exposures.empty() ? f.exposures_ms[i] : exposures[i],
                  "img" + std::to_string(i) + ".png"});
  return in;
}

/// The least-squares scale s that brings `got` closest to `truth` (G^-1 is recovered up to scale).
double alignScale(const std::array<float, 256>& got, const std::array<float, 256>& truth) {
  double gt = 0, gg = 0;
  for (std::size_t k = 0; k < 256; ++k) {
    gt += static_cast<double>(got[k]) * truth[k];
    gg += static_cast<double>(got[k]) * got[k];
  }
  return gt / gg;
}

/// RMS difference to the true G^-1 over all 256 values after scaling `got` by `scale`, in % of
/// the range 255.
double rmsErrorPercent(const std::array<float, 256>& got, const std::array<float, 256>& truth,
                       double scale) {
  double s = 0;
  for (std::size_t k = 0; k < 256; ++k) s += std::pow(scale * got[k] - truth[k], 2);
  return 100.0 * std::sqrt(s / 256) / 255.0;
}

struct Curve {
  sim::SimResponse response;
  double noise;
};

class ResponseRecovery : public ::testing::TestWithParam<Curve> {};

// Stated accuracy, 40 exposures of a 160 x 120 view, noise sigma 1-3 grey levels: after the
// least-squares scale (G^-1 is defined up to scale) the RMS error is below 0.5 % of the range
// (measured 0.05 - 0.4 %); the written scale (G^-1(255) = 255, extrapolated above the observed
// values) is within 3.5 % (measured up to 3.2 % for the S-curve, whose G^-1 is steepest there).
TEST_P(ResponseRecovery, MatchesTheTrueInverseResponse) {
  const auto [response, noise] = GetParam();
  const auto& f = sweep(response, noise);
  const auto r = calibrateResponse(asInput(f), {}, "sweep");
  const double scale = alignScale(r.inverse_response, f.truth.inverse_response);
  EXPECT_LT(rmsErrorPercent(r.inverse_response, f.truth.inverse_response, scale), 0.5)
      << "RMS error of G^-1 in % of the range after the scale normalisation";
  EXPECT_LT(rmsErrorPercent(r.inverse_response, f.truth.inverse_response, 1.0), 1.5)
      << "RMS error of G^-1 in % of the range as written";
  EXPECT_NEAR(scale, 1.0, 0.035);
  EXPECT_EQ(r.inverse_response[255], 255.0f);
  for (std::size_t k = 1; k < 256; ++k) EXPECT_GE(r.inverse_response[k], r.inverse_response[k - 1]);
  EXPECT_LE(r.first_observed, noise > 2 ? 12 : 8);
  EXPECT_GE(r.last_observed, noise > 2 ? 243 : 248);
  EXPECT_TRUE(r.non_monotonic.size() < 10u) << r.non_monotonic.size() << " non-monotonic values";
  EXPECT_NEAR(r.noise_sigma, noise, 0.3 * noise);
  // Every image with usable pixels has the brightness its exposure time predicts.
  int fitted = 0;
  for (const double s : r.exposure_scale) {
    if (std::isnan(s)) continue;
    EXPECT_NEAR(s, 1.0, 0.05);
    ++fitted;
  }
  EXPECT_GE(fitted, 20);
  for (const auto& w : r.warnings)
    if (noise <= 2 || w.find("limits the usable pixel values") == std::string::npos)
      ADD_FAILURE() << "unexpected warning: " << w;
  // The longest exposures are all white (with strong noise some clipped values stay in range).
  if (noise <= 2) {
    EXPECT_GE(r.skipped_saturated.size(), 4u);
  }
  EXPECT_EQ(r.images_used + r.skipped_saturated.size() + r.skipped_dark.size(), 40u);
}

INSTANTIATE_TEST_SUITE_P(Curves, ResponseRecovery,
                         ::testing::Values(Curve{sim::SimResponse::Gamma, 1.0},
                                           Curve{sim::SimResponse::SCurve, 1.0},
                                           Curve{sim::SimResponse::Linear, 1.0},
                                           Curve{sim::SimResponse::Gamma, 3.0}),
                         [](const auto& p) {
                           return sim::toString(p.param.response) + "_noise" +
                                  std::to_string(static_cast<int>(p.param.noise));
                         });

TEST(ResponseCalibration, MonotoneFitPoolsViolators) {
  const auto y = monotoneFit({1, 3, 2, 4, 0, 7}, {1, 1, 1, 1, 0, 2});
  EXPECT_DOUBLE_EQ(y[0], 1);
  EXPECT_DOUBLE_EQ(y[1], 2.5);
  EXPECT_DOUBLE_EQ(y[2], 2.5);
  EXPECT_DOUBLE_EQ(y[3], 4);
  EXPECT_DOUBLE_EQ(y[4], 0);  // weight 0: untouched
  EXPECT_DOUBLE_EQ(y[5], 7);
  const auto z = monotoneFit({5, 4, 3}, {1, 2, 3});
  EXPECT_NEAR(z[0], (5 + 8 + 9) / 6.0, 1e-12);
  EXPECT_EQ(z[0], z[2]);
}

void expectInputError(const std::vector<ExposedImage>& in, const std::vector<std::string>& texts,
                      const ResponseCalibrationOptions& o = {}) {
  try {
    calibrateResponse(in, o, "sweep");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("sweep: ", 0), 0u) << what;
    for (const auto& t : texts) EXPECT_NE(what.find(t), std::string::npos) << what;
  }
}

TEST(ResponseCalibration, SaturatedSweepSaysUseShorterExposures) {
  const auto& f = sweep(sim::SimResponse::Gamma);
  auto in = asInput(f);
  in.erase(in.begin(), in.begin() + 33);  // only the longest exposures: nearly all white
  expectInputError(in, {"saturated", "use shorter exposures"});
}

TEST(ResponseCalibration, DarkSweepSaysUseLongerExposures) {
  const auto& f = sweep(sim::SimResponse::Linear);
  auto in = asInput(f);
  in.resize(8);  // the shortest exposures: nearly all black
  expectInputError(in, {"dark", "use longer exposures"});
}

TEST(ResponseCalibration, NarrowExposureRangeIsRejected) {
  const auto& f = sweep(sim::SimResponse::Gamma);
  auto in = asInput(f);
  in = std::vector<ExposedImage>(in.begin() + 18, in.begin() + 22);
  expectInputError(in, {"span only", "nearly black to nearly white"});
}

TEST(ResponseCalibration, MissingOrBadExposureTimes) {
  const auto& f = sweep(sim::SimResponse::Gamma);
  auto in = asInput(f);
  in[7].exposure_ms = std::nan("");
  expectInputError(in, {"img7.png has exposure time", "third column of times.txt"});
  in[7].exposure_ms = -1;
  expectInputError(in, {"img7.png"});
  expectInputError(std::vector<ExposedImage>(in.begin(), in.begin() + 2), {"at least 3 images"});
}

TEST(ResponseCalibration, ImagesOfDifferentSizes) {
  const auto& f = sweep(sim::SimResponse::Gamma);
  auto in = asInput(f);
  ImageU8 small(10, 10, 100);
  in[3].image = small.view();
  expectInputError(in, {"img3.png is 10x10"});
}

TEST(ResponseCalibration, ExposureTimesThatDoNotBelongToTheImages) {
  const auto& f = sweep(sim::SimResponse::Gamma);
  // times.txt with its lines shuffled: exposures no longer match the images.
  std::vector<double> shuffled = f.exposures_ms;
  for (std::size_t i = 0; i + 7 < shuffled.size(); i += 7) std::swap(shuffled[i], shuffled[i + 5]);
  expectInputError(asInput(f, shuffled),
                   {"brightness does not follow exposure", "auto-gain", "record the sweep again"});
}

TEST(ResponseCalibration, AutoGainIsDetected) {
  // A camera whose auto-gain holds the brightness over most of the sweep: the images are formed
  // with exposure x gain, gain up to 16x, while the nominal exposures are reported.
  const auto o = sweepOptions(sim::SimResponse::Gamma);
  const auto times = sim::exposureSweepTimes(0.05, 400, 30);
  std::vector<double> formed;
  for (const double t : times) formed.push_back(t * std::clamp(8.0 / t, 1.0, 16.0));
  const auto f = sim::renderExposureSweep("loop", o, times, formed);
  expectInputError(asInput(f),
                   {"brightness does not follow exposure", "Auto-exposure or auto-gain"});

  // Forced through, the result carries the warning.
  ResponseCalibrationOptions force;
  force.allow_inconsistent = true;
  const auto r = calibrateResponse(asInput(f), force, "sweep");
  EXPECT_TRUE(std::any_of(r.warnings.begin(), r.warnings.end(), [](const std::string& w) {
    return w.find("brightness does not follow exposure") != std::string::npos;
  }));
}

}  // namespace
}  // namespace ldsm::calib
