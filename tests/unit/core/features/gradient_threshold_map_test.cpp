// GradientThresholdMap: the per-block gradient thresholds of the point selection.
#include "features/gradient_threshold_map.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "image/image_pyramid.h"
#include "ldsm/error.h"

namespace ldsm {
namespace {

/// Left half flat, right half strong random texture.
ImagePyramid halfTextured(int w, int h) {
  ImageF img(w, h);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.f, 255.f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img(x, y) = x < w / 2 ? 100.f : u(rng);
  ImagePyramid p(w, h, 1);
  p.build(img.view());
  return p;
}

TEST(GradientThresholdMap, RowAccessMatchesThePerPixelThreshold) {
  const int w = 97, h = 61;  // not multiples of the block size
  const ImagePyramid p = halfTextured(w, h);
  GradientThresholdMap map(w, h, 32);
  map.compute(p.gradients(0), 7.f);
  const int* columns = map.blockColumns();
  for (int y = 0; y < h; ++y) {
    const float* row = map.rowThresholdsSq(y);
    for (int x = 0; x < w; ++x) ASSERT_EQ(row[columns[x]], map.thresholdSq(x, y)) << x << "," << y;
  }
}

TEST(GradientThresholdMap, TexturedBlocksGetHigherThresholdsThanFlatOnes) {
  const int w = 128, h = 64;
  const ImagePyramid p = halfTextured(w, h);
  GradientThresholdMap map(w, h, 32);
  map.compute(p.gradients(0), 7.f);
  for (int y = 0; y < h; y += 7) {
    EXPECT_GE(std::sqrt(map.thresholdSq(2, y)), 7.f - 1e-4f);  // never below min_gradient
    EXPECT_GT(map.thresholdSq(w - 3, y), map.thresholdSq(2, y));
  }
}

TEST(GradientThresholdMap, RefusesAnotherSizeAndABadBlockSize) {
  const ImagePyramid p = halfTextured(64, 48);
  GradientThresholdMap map(64, 40, 16);
  EXPECT_THROW(map.compute(p.gradients(0), 7.f), InputError);
  EXPECT_THROW(GradientThresholdMap(64, 48, 0), ConfigError);
  EXPECT_THROW(GradientThresholdMap(0, 48, 16), InputError);
}

}  // namespace
}  // namespace ldsm
