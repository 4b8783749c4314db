// The affine brightness transfer between two frames (model/affine_light.h): what it maps is what
// the photometric model I = t e^a L + b (scene radiance L, exposure t, frame parameters a, b)
// predicts, and transfers compose and invert like the maps they are.
#include "model/affine_light.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace ldsm {
namespace {

struct Frame {
  double exposure;
  AffineLight aff;
  /// The intensity this frame records of radiance L.
  double intensity(double L) const { return exposure * std::exp(aff.a) * L + aff.b; }
};

Frame randomFrame(std::mt19937& rng) {
  std::uniform_real_distribution<double> t(0.002, 0.04), a(-1.0, 1.0), b(-20.0, 20.0);
  return {t(rng), {a(rng), b(rng)}};
}

Eigen::Vector2d transfer(const Frame& host, const Frame& target) {
  return affineTransfer(host.exposure, target.exposure, host.aff, target.aff);
}

TEST(AffineLight, TransferBetweenIdenticalFramesIsTheIdentity) {
  std::mt19937 rng(1);
  for (int i = 0; i < 20; ++i) {
    const Frame f = randomFrame(rng);
    const Eigen::Vector2d s = transfer(f, f);
    EXPECT_NEAR(s[0], 1.0, 1e-12);
    EXPECT_NEAR(s[1], 0.0, 1e-12);
  }
}

TEST(AffineLight, TransferMapsHostIntensitiesToTheTargetsOfTheSameRadiance) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> radiance(0.0, 5000.0);
  for (int i = 0; i < 50; ++i) {
    const Frame h = randomFrame(rng), t = randomFrame(rng);
    const Eigen::Vector2d s = transfer(h, t);
    EXPECT_GT(s[0], 0.0);
    for (int k = 0; k < 5; ++k) {
      const double L = radiance(rng);
      EXPECT_NEAR(s[0] * h.intensity(L) + s[1], t.intensity(L),
                  1e-9 * (1.0 + std::abs(t.intensity(L))));
    }
  }
}

TEST(AffineLight, ScaleIsLinearInTheExposureRatio) {
  const AffineLight host{0.2, 5.0}, target{-0.1, -3.0};
  const Eigen::Vector2d one = affineTransfer(0.01, 0.01, host, target);
  const Eigen::Vector2d twice = affineTransfer(0.01, 0.02, host, target);
  EXPECT_NEAR(one[0], std::exp(-0.3), 1e-12);
  EXPECT_NEAR(twice[0], 2.0 * one[0], 1e-12);
  // The offset is the target's b less the scaled host's b.
  EXPECT_NEAR(one[1], -3.0 - one[0] * 5.0, 1e-12);
  EXPECT_NEAR(twice[1], -3.0 - twice[0] * 5.0, 1e-12);
}

TEST(AffineLight, TransfersComposeThroughAnIntermediateFrame) {
  std::mt19937 rng(3);
  for (int i = 0; i < 50; ++i) {
    const Frame a = randomFrame(rng), b = randomFrame(rng), c = randomFrame(rng);
    const Eigen::Vector2d ab = transfer(a, b), bc = transfer(b, c), ac = transfer(a, c);
    // (x -> bc0 (ab0 x + ab1) + bc1) == (x -> ac0 x + ac1)
    EXPECT_NEAR(bc[0] * ab[0], ac[0], 1e-12 * ac[0]);
    EXPECT_NEAR(bc[0] * ab[1] + bc[1], ac[1], 1e-9);
  }
}

TEST(AffineLight, TransferBackIsTheInverseMap) {
  std::mt19937 rng(4);
  for (int i = 0; i < 50; ++i) {
    const Frame h = randomFrame(rng), t = randomFrame(rng);
    const Eigen::Vector2d fwd = transfer(h, t), back = transfer(t, h);
    EXPECT_NEAR(back[0] * fwd[0], 1.0, 1e-12);
    EXPECT_NEAR(back[0] * fwd[1] + back[1], 0.0, 1e-9);
  }
}

TEST(AffineLight, DefaultIsTheNeutralBrightness) {
  const AffineLight none;
  EXPECT_EQ(none.a, 0.0);
  EXPECT_EQ(none.b, 0.0);
  const Eigen::Vector2d s = affineTransfer(0.02, 0.005, none, none);
  EXPECT_NEAR(s[0], 0.25, 1e-12);  // only the exposures differ
  EXPECT_EQ(s[1], 0.0);
}

}  // namespace
}  // namespace ldsm
