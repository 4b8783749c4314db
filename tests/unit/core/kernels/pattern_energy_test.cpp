// The depth search's pattern energy (kernels/pattern_energy.h), for the selected instruction set
// and the plain-C++ vector, against the scalar reference on random textures, rotated pattern
// offsets, sub-pixel positions and residuals on both sides of the Huber threshold: the same
// arithmetic summed in the same order, so the two must be equal.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "kernels/pattern_energy.h"
#include "ldsm/image.h"

namespace ldsm {
namespace simd {
namespace {

template <class V>
class PatternEnergyTest : public ::testing::Test {};
using VecTypes = ::testing::Types<Vec4, Vec4Scalar>;
TYPED_TEST_SUITE(PatternEnergyTest, VecTypes, );

Image<GradientPixel> randomTexture(int w, int h, std::mt19937& rng) {
  std::uniform_real_distribution<float> U(0.f, 255.f);
  Image<GradientPixel> g(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) g(x, y) = {U(rng), 0.f, 0.f};  // the energy reads intensities
  return g;
}

TYPED_TEST(PatternEnergyTest, AgreesWithTheReference) {
  std::mt19937 rng(7);
  const Image<GradientPixel> img = randomTexture(64, 48, rng);
  std::uniform_real_distribution<float> U(-1.f, 1.f);
  for (int trial = 0; trial < 2000; ++trial) {
    PatternEnergyParams m;
    m.image = img.view();
    m.huber = 9.f * (1.f + 0.5f * U(rng));
    // A rotated and scaled pattern (the rotation-only homography's local map).
    const float c = 1.f + 0.3f * U(rng), s = 0.4f * U(rng);
    for (int k = 0; k < kPatternSize; ++k) {
      const float dx = static_cast<float>(kPatternOffsets[k][0]);
      const float dy = static_cast<float>(kPatternOffsets[k][1]);
      m.ox[k] = c * dx - s * dy;
      m.oy[k] = s * dx + c * dy;
      m.expected[k] = 128.f + 127.f * U(rng);
      m.weights[k] = 0.5f + 0.5f * U(rng);
    }
    const float x = 10.f + 40.f * (0.5f + 0.5f * U(rng));
    const float y = 10.f + 25.f * (0.5f + 0.5f * U(rng));
    const float ref = reference::patternEnergy(m, x, y);
    const float got = patternEnergy<TypeParam>(m, x, y);
    ASSERT_EQ(got, ref) << "trial " << trial;
  }
}

TYPED_TEST(PatternEnergyTest, ZeroAtTheExactMatch) {
  std::mt19937 rng(11);
  const Image<GradientPixel> img = randomTexture(32, 32, rng);
  PatternEnergyParams m;
  m.image = img.view();
  for (int k = 0; k < kPatternSize; ++k) {
    m.ox[k] = static_cast<float>(kPatternOffsets[k][0]);
    m.oy[k] = static_cast<float>(kPatternOffsets[k][1]);
    m.expected[k] = img(16 + kPatternOffsets[k][0], 15 + kPatternOffsets[k][1]).intensity;
    m.weights[k] = 1.f;
  }
  EXPECT_EQ(patternEnergy<TypeParam>(m, 16.f, 15.f), 0.f);
  EXPECT_GT(patternEnergy<TypeParam>(m, 17.f, 15.f), 0.f);
}

}  // namespace
}  // namespace simd
}  // namespace ldsm
