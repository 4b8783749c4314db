// Image formation: exposure, vignette, response, noise and 8-bit rounding as specified, checked
// through the photometric calibration the source exports (G^-1, V).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "ldsm/drivers/sim/image_formation.h"
#include "ldsm/drivers/sim/sim_source.h"
#include "ldsm/error.h"
#include "sim_test_support.h"

namespace ldsm::drivers::sim {
namespace {

PinholeIntrinsics smallCamera() {
  SimOptions o;
  o.width = 64;
  o.height = 48;
  return simIntrinsics(o);
}

// G^-1 by linear interpolation of the exported 256-entry table.
double inverseResponse(const std::array<float, 256>& inv, double v) {
  return inv[static_cast<std::size_t>(v)];
}

TEST(ImageFormation, ResponseTablesFollowTheCurves) {
  for (SimResponse r : {SimResponse::Linear, SimResponse::Gamma, SimResponse::SCurve}) {
    SimOptions o;
    o.response = r;
    const ImageFormation f(o, smallCamera());
    for (double e = 0.0; e <= 1.0; e += 0.01)
      EXPECT_NEAR(f.responseGrey(e), 255.0 * responseCurve(r, e),
                  r == SimResponse::Linear ? 1e-3 : 0.05)
          << toString(r) << " e " << e;
    // The exported inverse response inverts the table, rises, and spans [0, 255].
    const auto& inv = f.inverseResponse();
    EXPECT_EQ(inv[0], 0.0f);
    EXPECT_EQ(inv[255], 255.0f);
    for (int v = 1; v < 256; ++v) EXPECT_GT(inv[v], inv[v - 1]) << toString(r) << " v " << v;
    for (int v = 1; v < 255; ++v) EXPECT_NEAR(f.responseGrey(inv[v] / 255.0), v, 0.02);
  }
  EXPECT_NEAR(responseCurve(SimResponse::Gamma, 0.5), std::pow(0.5, 1 / 2.2), 1e-12);
  EXPECT_EQ(responseCurve(SimResponse::Linear, 2.0), 1.0);  // saturates
}

TEST(ImageFormation, LinearNoiselessImageIsTheRoundedExposure) {
  SimOptions o;
  o.response = SimResponse::Linear;
  o.vignette = 0.0;
  o.noise_sigma = 0.0;
  const ImageFormation f(o, smallCamera());
  ImageF irr(64, 48);
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) irr(x, y) = static_cast<float>((x + 64 * y) / 3072.0 * 1.2);
  ImageU8 out;
  f.apply(irr, 20.0, 0, out);  // exposure 20 ms: e = B
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) {
      const double e = std::min(1.0, static_cast<double>(irr(x, y)));
      EXPECT_NEAR(out(x, y), 255.0 * e, 0.5 + 1e-3) << x << "," << y;
    }
}

TEST(ImageFormation, DoublingExposureDoublesTheLinearisedIntensity) {
  for (SimResponse r : {SimResponse::Gamma, SimResponse::SCurve}) {
    for (double sigma : {0.0, 1.0}) {
      SimOptions o;
      o.response = r;
      o.noise_sigma = sigma;
      SimSource src(test::sharedScene("short"), [&] {
        SimOptions s = o;
        s.width = 160;
        s.height = 120;
        return s;
      }());
      const auto& inv = src.photometricCalibration().inverse_response;
      ImageF irr;
      src.renderer().renderIrradiance(src.groundTruth()[10].pose, irr);
      ImageU8 a, b;
      src.imageFormation().apply(irr, 6.0, 1, a);
      src.imageFormation().apply(irr, 12.0, 2, b);
      std::vector<double> ratios;
      for (int y = 0; y < 120; ++y)
        for (int x = 0; x < 160; ++x) {
          if (a(x, y) < 40 || b(x, y) > 245) continue;
          ratios.push_back(inverseResponse(inv, b(x, y)) / inverseResponse(inv, a(x, y)));
        }
      ASSERT_GT(ratios.size(), 5000u);
      std::sort(ratios.begin(), ratios.end());
      SCOPED_TRACE(toString(r) + " sigma " + std::to_string(sigma));
      EXPECT_NEAR(ratios[ratios.size() / 2], 2.0, 0.02);
      EXPECT_NEAR(ratios[ratios.size() / 10], 2.0, sigma > 0 ? 0.15 : 0.06);
      EXPECT_NEAR(ratios[ratios.size() * 9 / 10], 2.0, sigma > 0 ? 0.15 : 0.06);
    }
  }
}

TEST(ImageFormation, VignetteIsAppliedAsExported) {
  SimOptions o;
  o.vignette = 0.4;
  o.noise_sigma = 0.0;
  SimSource src(test::sharedScene("short"), [&] {
    SimOptions s = o;
    s.width = 64;
    s.height = 48;
    return s;
  }());
  const ImageF& V = src.photometricCalibration().vignette;
  ASSERT_EQ(V.width(), 64);
  EXPECT_NEAR(V(0, 0), 0.6, 1e-6);  // 1 - vignette at the corners
  EXPECT_NEAR(V(63, 47), 0.6, 1e-6);
  EXPECT_GT(V(32, 24), 0.999);
  const auto& inv = src.photometricCalibration().inverse_response;
  ImageF flat(64, 48, 0.5f);
  ImageU8 out;
  src.imageFormation().apply(flat, 20.0, 0, out);  // e = 0.5 V
  for (int y = 0; y < 48; y += 3)
    for (int x = 0; x < 64; x += 3) {
      // G^-1(I) / 255 = e within rounding: one grey level is at most ~1.5% here.
      EXPECT_NEAR(inverseResponse(inv, out(x, y)) / 255.0, 0.5 * V(x, y), 0.012) << x << "," << y;
    }
}

TEST(ImageFormation, NoiseHasTheRequestedSigmaAndIsKeyed) {
  SimOptions o;
  o.noise_sigma = 3.0;
  o.vignette = 0.0;
  o.response = SimResponse::Linear;
  const ImageFormation f(o, smallCamera());
  ImageF flat(64, 48, 0.5f);
  ImageU8 a, b, c;
  f.apply(flat, 20.0, 11, a);
  f.apply(flat, 20.0, 11, b);
  f.apply(flat, 20.0, 12, c);
  double sum = 0, sum2 = 0;
  int same = 0;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) {
      sum += a(x, y);
      sum2 += a(x, y) * a(x, y);
      EXPECT_EQ(a(x, y), b(x, y));
      same += a(x, y) == c(x, y);
    }
  const double n = 64 * 48, mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(mean, 127.5, 0.3);
  EXPECT_NEAR(sd, std::sqrt(9.0 + 1.0 / 12.0), 0.15);
  EXPECT_LT(same, n / 3);  // a different key gives different noise
}

TEST(ImageFormation, ExposureScheduleIsSmoothAndBounded) {
  SimOptions o;
  EXPECT_EQ(simExposureMs(o, 3.0), o.exposure_ms);
  o.exposure_changes = true;
  double lo = 1e9, hi = 0, prev = simExposureMs(o, 0.0);
  for (int i = 1; i < 3000; ++i) {
    const double e = simExposureMs(o, i / 30.0);
    lo = std::min(lo, e);
    hi = std::max(hi, e);
    EXPECT_LT(std::fabs(std::log(e / prev)), 0.03) << "frame " << i;
    prev = e;
  }
  EXPECT_GE(lo, 0.5 * o.exposure_ms - 1e-9);
  EXPECT_LE(hi, 2.0 * o.exposure_ms + 1e-9);
  EXPECT_LT(lo, 0.6 * o.exposure_ms);
  EXPECT_GT(hi, 1.7 * o.exposure_ms);
}

TEST(ImageFormation, WrongIrradianceSizeIsAnInputError) {
  const ImageFormation f(SimOptions{}, smallCamera());
  ImageU8 out;
  EXPECT_THROW(f.apply(ImageF(10, 10), 10.0, 0, out), InputError);
}

}  // namespace
}  // namespace ldsm::drivers::sim
