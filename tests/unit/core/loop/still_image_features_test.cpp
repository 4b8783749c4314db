#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "ldsm/error.h"
#include "loop/binary_kmajority.h"
#include "loop/still_image_features.h"

namespace ldsm::loop {
namespace {

ImageU8 blocks(int w, int h, int block, std::uint64_t seed) {
  ImageU8 img(w, h, 0);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      SplitMix64 cell(seed * 1000003u + static_cast<std::uint64_t>((y / block) * 4096 + x / block));
      img(x, y) = static_cast<std::uint8_t>(cell.below(256));
    }
  }
  return img;
}

TEST(StillImageFeatures, DetectsOnEveryLevelWithinTheBudget) {
  const ImageU8 img = blocks(320, 240, 9, 3);
  StillImageFeatureSettings s;
  s.max_corners = 400;
  StillImageFeatures f(320, 240, s);
  StillFeatures out;
  const int n = f.compute(img.view(), out);
  EXPECT_GT(n, 200);
  EXPECT_LE(n, 400);
  ASSERT_EQ(out.pixels.size(), static_cast<std::size_t>(n));
  ASSERT_EQ(out.levels.size(), static_cast<std::size_t>(n));
  ASSERT_EQ(out.descriptors.size(), static_cast<std::size_t>(n));
  std::set<int> levels(out.levels.begin(), out.levels.end());
  EXPECT_EQ(levels.size(), 5u);
  for (std::size_t i = 0; i < out.pixels.size(); ++i) {
    // Every feature's patch fits at its level.
    const float scale = std::pow(1.2f, static_cast<float>(out.levels[i]));
    EXPECT_GE(out.pixels[i].x() / scale, 14.5f);
    EXPECT_LE(out.pixels[i].x() / scale, 320.f / scale - 15.5f);
  }
  // Engine-like: level 0 only.
  s.detection_levels = 1;
  StillImageFeatures level0(320, 240, s);
  level0.compute(img.view(), out);
  EXPECT_EQ(std::set<int>(out.levels.begin(), out.levels.end()), std::set<int>{0});
}

TEST(StillImageFeatures, RejectsBadSettingsAndSizes) {
  StillImageFeatureSettings s;
  s.detection_levels = 6;  // more than orb.levels
  EXPECT_THROW(StillImageFeatures(100, 100, s), ConfigError);
  s = StillImageFeatureSettings();
  s.max_corners = 0;
  EXPECT_THROW(StillImageFeatures(100, 100, s), ConfigError);
  EXPECT_THROW(StillImageFeatures(0, 100), InputError);
  StillImageFeatures f(100, 100);
  ImageU8 wrong(90, 100, 0);
  StillFeatures out;
  EXPECT_THROW(f.compute(wrong.view(), out), InputError);
}

}  // namespace
}  // namespace ldsm::loop
