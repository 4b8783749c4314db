#include "image/interpolation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "image/image_pyramid.h"

namespace ldsm {
namespace {

TEST(Interpolation, HandComputedValues) {
  // [1 2]
  // [3 4]
  const float data[] = {1.f, 2.f, 3.f, 4.f};
  const ImageView<const float> img(data, 2, 2);
  EXPECT_FLOAT_EQ(interpolateBilinear(img, 0.f, 0.f), 1.f);
  // top 1.25, bottom 3.25, halfway down: 2.25
  EXPECT_FLOAT_EQ(interpolateBilinear(img, 0.25f, 0.5f), 2.25f);
  // 0.9 * 0.1 * 2 + 0.1 * 0.1 * 1 + 0.9 * 0.9 * 4 + 0.1 * 0.9 * 3 = 0.18 + 0.01 + 3.24 + 0.27
  EXPECT_FLOAT_EQ(interpolateBilinear(img, 0.9f, 0.9f), 3.7f);
}

TEST(Interpolation, IntegerPositionsReturnThePixelAndStrideIsHonoured) {
  // 4 x 3 image inside a buffer of stride 7 filled with garbage beyond the width.
  std::vector<float> buf(7 * 3, 1e6f);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 4; ++x) buf[y * 7 + x] = static_cast<float>(x * 10 + y);
  const ImageView<const float> img(buf.data(), 4, 3, 7);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x)
      EXPECT_EQ(interpolateBilinear(img, static_cast<float>(x), static_cast<float>(y)),
                static_cast<float>(x * 10 + y));
  // Just below the last valid position: no garbage is read.
  EXPECT_NEAR(interpolateBilinear(img, 2.999f, 1.999f), 10 * 2.999 + 1.999, 1e-4);
}

TEST(Interpolation, ReproducesBilinearFunctionsExactly) {
  // f = a + b x + c y + d x y is reproduced exactly by bilinear interpolation.
  const int w = 9;
  const int h = 7;
  std::vector<float> data(w * h);
  auto f = [](double x, double y) { return 3.0 + 0.5 * x - 1.25 * y + 0.125 * x * y; };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) data[y * w + x] = static_cast<float>(f(x, y));
  const ImageView<const float> img(data.data(), w, h);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> ux(0.f, w - 1.001f);
  std::uniform_real_distribution<float> uy(0.f, h - 1.001f);
  for (int i = 0; i < 200; ++i) {
    const float x = ux(rng);
    const float y = uy(rng);
    ASSERT_TRUE(isInsideForBilinear(img, x, y));
    EXPECT_NEAR(interpolateBilinear(img, x, y), f(x, y), 2e-5);
  }
}

TEST(Interpolation, PackedLevelInterpolatesAllThreeChannels) {
  // Channels: intensity = x + 10 y, dx = 2 y, dy = -x (arbitrary, each bilinear).
  const int w = 5;
  const int h = 4;
  std::vector<GradientPixel> data(w * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      data[y * w + x] = {static_cast<float>(x + 10 * y), static_cast<float>(2 * y),
                         static_cast<float>(-x)};
  const ImageView<const GradientPixel> img(data.data(), w, h);
  const GradientPixel g = interpolateBilinear(img, 1.5f, 2.25f);
  EXPECT_FLOAT_EQ(g.intensity, 1.5f + 22.5f);
  EXPECT_FLOAT_EQ(g.dx, 4.5f);
  EXPECT_FLOAT_EQ(g.dy, -1.5f);
  // Hand-computed corner weights at (0.5, 0.5): mean of the four pixels.
  const GradientPixel c = interpolateBilinear(img, 0.5f, 0.5f);
  EXPECT_FLOAT_EQ(c.intensity, (0.f + 1.f + 10.f + 11.f) / 4);
}

TEST(Interpolation, AgreesWithScalarInterpolationOnAPyramidLevel) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  std::vector<float> data(32 * 24);
  for (float& v : data) v = u(rng);
  ImagePyramid p(32, 24, 2);
  p.build(ImageView<const float>(data.data(), 32, 24));
  for (int i = 0; i < 50; ++i) {
    const float x = 1.f + 13.f * u(rng);
    const float y = 1.f + 9.f * u(rng);
    const GradientPixel g = interpolateBilinear(p.gradients(1), x, y);
    ImageF level1;
    p.copyIntensity(1, level1);
    const float scalar = interpolateBilinear(level1.view(), x, y);
    EXPECT_NEAR(g.intensity, scalar, 1e-6);
    // The intensity-only interpolation of the packed level has the scalar one's arithmetic.
    EXPECT_EQ(interpolateIntensity(p.gradients(1), x, y), scalar);
  }
}

TEST(Interpolation, BoundsCheck) {
  EXPECT_TRUE(isInsideForBilinear(0.f, 0.f, 10, 8));
  EXPECT_TRUE(isInsideForBilinear(8.999f, 6.999f, 10, 8));
  EXPECT_FALSE(isInsideForBilinear(9.f, 3.f, 10, 8));  // would read x = 10
  EXPECT_FALSE(isInsideForBilinear(3.f, 7.f, 10, 8));  // would read y = 8
  EXPECT_FALSE(isInsideForBilinear(-0.001f, 3.f, 10, 8));
  EXPECT_FALSE(isInsideForBilinear(3.f, -1e-6f, 10, 8));
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(isInsideForBilinear(nan, 3.f, 10, 8));
  EXPECT_FALSE(isInsideForBilinear(3.f, nan, 10, 8));
  EXPECT_FALSE(isInsideForBilinear(std::numeric_limits<float>::infinity(), 3.f, 10, 8));
  // With a margin of 2 pixels: 2 <= x < 7.
  EXPECT_TRUE(isInsideForBilinear(2.f, 2.f, 10, 8, 2.f));
  EXPECT_FALSE(isInsideForBilinear(1.9f, 2.f, 10, 8, 2.f));
  EXPECT_FALSE(isInsideForBilinear(7.f, 2.f, 10, 8, 2.f));
  EXPECT_TRUE(isInsideForBilinear(6.99f, 4.99f, 10, 8, 2.f));
  // Degenerate images have no valid position.
  EXPECT_FALSE(isInsideForBilinear(0.f, 0.f, 1, 5));
  EXPECT_FALSE(isInsideForBilinear(0.f, 0.f, 0, 0));
  const std::vector<float> data(12, 0.f);
  EXPECT_TRUE(isInsideForBilinear(ImageView<const float>(data.data(), 4, 3), 2.5f, 1.5f));
  EXPECT_FALSE(isInsideForBilinear(ImageView<const float>(data.data(), 4, 3), 3.f, 1.5f));
}

}  // namespace
}  // namespace ldsm
