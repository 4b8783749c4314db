// Mip chains: sizes, padding, filtering and the reference sampler.
#include <gtest/gtest.h>

#include <cmath>

#include "ldsm/drivers/sim/mip_texture.h"
#include "ldsm/error.h"

namespace ldsm::drivers::sim {
namespace {

TEST(MipTexture, RepeatingChainHalvesToOneTexelAndKeepsTheMean) {
  ImageF base(16, 8);
  double sum = 0.0;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 16; ++x) {
      base(x, y) = static_cast<float>((x * 7 + y * 3) % 11) / 10.0f;
      sum += base(x, y);
    }
  const MipTexture t = buildMipTexture(base, true, 0.01);
  ASSERT_EQ(t.levelCount(), 5);  // 16x8, 8x4, 4x2, 2x1, 1x1
  EXPECT_EQ(t.levels[1].width, 8);
  EXPECT_EQ(t.levels[1].height, 4);
  EXPECT_EQ(t.levels[4].width, 1);
  EXPECT_EQ(t.levels[4].height, 1);
  EXPECT_DOUBLE_EQ(t.levels[3].scale_u, 1.0 / 8);
  EXPECT_DOUBLE_EQ(t.levels[3].scale_v, 1.0 / 8);
  // The [1/4 1/2 1/4] filter with wrapping preserves the mean at every level.
  for (const MipLevel& l : t.levels) {
    double s = 0.0;
    for (int y = 0; y < l.height; ++y)
      for (int x = 0; x < l.width; ++x) s += l.at(x, y);
    EXPECT_NEAR(s / (l.width * l.height), sum / 128.0, 1e-5);
    // Padding repeats the first column and row.
    for (int y = 0; y <= l.height; ++y) EXPECT_EQ(l.at(l.width, y), l.at(0, y % l.height));
  }
}

TEST(MipTexture, ClampedChainStopsAtTwoTexelsAndTracksScalesPerAxis) {
  ImageF base(40, 3, 0.5f);
  base(39, 2) = 1.0f;
  const MipTexture t = buildMipTexture(base, false, 0.02);
  const MipLevel& last = t.levels.back();
  EXPECT_EQ(last.width, 2);
  EXPECT_EQ(last.height, 2);
  // v shrinks once (3 -> 2), u several times (40, 21, 11, 6, 4, 3, 2).
  EXPECT_EQ(t.levelCount(), 7);
  EXPECT_DOUBLE_EQ(t.levels[1].scale_v, 0.5);
  EXPECT_DOUBLE_EQ(t.levels[3].scale_v, 0.5);
  EXPECT_DOUBLE_EQ(t.levels[3].scale_u, 1.0 / 8);
  // Padding repeats the last texel; the sampler clamps outside the texture.
  EXPECT_EQ(t.levels[0].at(40, 2), 1.0f);
  EXPECT_NEAR(sampleLevelBilinear(t, 0, 100.0, 100.0), 1.0, 1e-7);
  EXPECT_NEAR(sampleLevelBilinear(t, 0, -5.0, 0.0), 0.5, 1e-7);
}

TEST(MipTexture, BilinearSamplerInterpolatesAndWraps) {
  ImageF base(4, 4, 0.0f);
  base(1, 1) = 1.0f;
  const MipTexture t = buildMipTexture(base, true, 0.01);
  EXPECT_NEAR(sampleLevelBilinear(t, 0, 1.0, 1.0), 1.0, 1e-12);
  EXPECT_NEAR(sampleLevelBilinear(t, 0, 1.5, 1.0), 0.5, 1e-12);
  EXPECT_NEAR(sampleLevelBilinear(t, 0, 0.5, 0.5), 0.25, 1e-12);
  EXPECT_NEAR(sampleLevelBilinear(t, 0, 1.25 + 4.0, 1.0 - 8.0), 0.75, 1e-12);
  // Level 1 (2x2) at level-0 coordinates: texel (0, 0) sits at level-0 (0, 0), (1, 1) at (2, 2).
  EXPECT_NEAR(sampleLevelBilinear(t, 1, 0.0, 0.0), t.levels[1].at(0, 0), 1e-12);
  EXPECT_NEAR(sampleLevelBilinear(t, 1, 2.0, 2.0), t.levels[1].at(1, 1), 1e-12);
}

TEST(MipTexture, RejectsBadSizes) {
  EXPECT_THROW(buildMipTexture(ImageF(12, 8), true, 0.01), InputError);
  EXPECT_THROW(buildMipTexture(ImageF(1, 8), false, 0.01), InputError);
  EXPECT_THROW(buildMipTexture(ImageF(4, 4), true, 0.0), InputError);
}

}  // namespace
}  // namespace ldsm::drivers::sim
