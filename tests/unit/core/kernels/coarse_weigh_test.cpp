// The coarse tracker's robust weighting: the SIMD kernel (selected instruction set and plain C++)
// against the per-point reference, bit for bit, on random residuals and gradients with residuals
// at and around the Huber threshold and the cutoffs, zero, negative and not finite, with and
// without the gradient weight.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "kernels/coarse_weigh.h"

namespace ldsm {
namespace simd {
namespace {

template <class V>
class CoarseWeighTest : public ::testing::Test {};
using VecTypes = ::testing::Types<Vec4, Vec4Scalar>;
TYPED_TEST_SUITE(CoarseWeighTest, VecTypes, );

bool sameBits(float a, float b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

TYPED_TEST(CoarseWeighTest, MatchesTheReferenceBitForBit) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> U(-1.f, 1.f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  int counts[2] = {0, 0};  // outliers, inliers
  for (const float c2 : {0.f, 2500.f}) {
    CoarseWeighting p;
    p.c2 = c2;
    p.huber = 9.f;
    p.cutoff = 27.f;
    p.outlier_cost = 2.f * p.huber * p.cutoff - p.huber * p.huber;
    p.base_cutoff = 20.f;
    // Exactly at the thresholds, both signs, zero, and not finite.
    std::vector<float> special = {0.f,   -0.f, 9.f, -9.f, 27.f,   -27.f,     20.f,
                                  -20.f, nan,  inf, -inf, 1e-30f, 8.999999f, 27.00001f};
    for (int trial = 0; trial < 4000; ++trial) {
      alignas(16) float r[4], g2[4];
      for (int l = 0; l < 4; ++l) {
        const int pick = static_cast<int>(rng() % 5);
        r[l] = pick == 0 ? special[rng() % special.size()] : 40.f * U(rng);
        g2[l] = pick == 1 ? 0.f : 1e4f * (0.5f + 0.5f * U(rng));
      }
      CoarseWeights4 got;
      weighCoarse4<TypeParam>(p, r, g2, got);
      for (int l = 0; l < 4; ++l) {
        const CoarseWeightedPoint ref = reference::weighCoarsePoint(p, r[l], g2[l]);
        ASSERT_EQ(((got.inlier >> l) & 1) != 0, ref.inlier) << r[l];
        ASSERT_EQ(((got.base_outlier >> l) & 1) != 0, ref.base_outlier) << r[l];
        ASSERT_TRUE(sameBits(got.energy[l], ref.energy)) << r[l] << " " << g2[l];
        ASSERT_TRUE(sameBits(got.huber[l], ref.huber)) << r[l];
        if (ref.inlier) {
          ASSERT_TRUE(sameBits(got.weight[l], ref.weight)) << r[l] << " " << g2[l];
        }
        ++counts[ref.inlier ? 1 : 0];
      }
    }
  }
  EXPECT_GT(counts[0], 2000);
  EXPECT_GT(counts[1], 10000);
}

// What the weights mean: an inlier inside the Huber threshold has weight gw and cost r^2, one
// beyond it the Huber weight k / |r|; an outlier (NaN too) costs the outlier cost and no weight.
TEST(CoarseWeigh, ReferenceFollowsTheDefinition) {
  CoarseWeighting p;
  p.c2 = 100.f;
  p.huber = 4.f;
  p.cutoff = 10.f;
  p.outlier_cost = 64.f;
  p.base_cutoff = 8.f;
  const CoarseWeightedPoint small = reference::weighCoarsePoint(p, -2.f, 300.f);
  EXPECT_TRUE(small.inlier);
  EXPECT_FALSE(small.base_outlier);
  EXPECT_FLOAT_EQ(small.weight, 0.25f);  // gw = 100 / 400
  EXPECT_FLOAT_EQ(small.huber, 4.f);
  EXPECT_FLOAT_EQ(small.energy, 1.f);
  const CoarseWeightedPoint large = reference::weighCoarsePoint(p, 9.f, 0.f);
  EXPECT_TRUE(large.inlier);
  EXPECT_TRUE(large.base_outlier);
  EXPECT_FLOAT_EQ(large.weight, 4.f / 9.f);
  EXPECT_FLOAT_EQ(large.huber, 2.f * 4.f * 9.f - 16.f);
  const CoarseWeightedPoint nan =
      reference::weighCoarsePoint(p, std::numeric_limits<float>::quiet_NaN(), 0.f);
  EXPECT_FALSE(nan.inlier);
  EXPECT_FALSE(nan.base_outlier);
  EXPECT_EQ(nan.huber, 64.f);
  EXPECT_EQ(nan.energy, 64.f);
  EXPECT_EQ(nan.weight, 0.f);
}

}  // namespace
}  // namespace simd
}  // namespace ldsm
