// Squared gradient magnitudes and histogram bins of packed rows: the SIMD kernels (selected
// instruction set and plain C++) against the per-pixel reference, bit for bit, for every row
// length, with magnitudes beyond the last bin and exactly on bin edges.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "image/gradient_magnitude.h"

namespace ldsm {
namespace simd {
namespace {

template <class V>
class GradientMagnitudeTest : public ::testing::Test {};
using VecTypes = ::testing::Types<Vec4, Vec4Scalar>;
TYPED_TEST_SUITE(GradientMagnitudeTest, VecTypes, );

TYPED_TEST(GradientMagnitudeTest, SquaresAndBinsEqualThePerPixelRow) {
  using V = TypeParam;
  std::mt19937 rng(12);
  std::uniform_real_distribution<float> g(-80.f, 80.f);
  std::uniform_int_distribution<int> coin(0, 4);
  for (int n = 0; n <= 41; ++n) {
    std::vector<GradientPixel> row(static_cast<std::size_t>(n) + 1);
    for (GradientPixel& p : row) {
      p = {g(rng), g(rng), g(rng)};
      if (coin(rng) == 0) p = {p.intensity, 3.f, 4.f};  // magnitude exactly 5: a bin edge
      if (coin(rng) == 1) p = {p.intensity, 0.f, 0.f};
    }
    std::vector<float> a(static_cast<std::size_t>(n), -1.f), b = a;
    reference::gradientMagnitudeSqRow(row.data(), n, a.data());
    gradientMagnitudeSqRow<V>(row.data(), n, b.data());
    ASSERT_EQ(a, b) << "row length " << n;
    std::vector<std::int32_t> ba(static_cast<std::size_t>(n), -1), bb = ba;
    reference::gradientMagnitudeBinRow(row.data(), n, 49, ba.data());
    gradientMagnitudeBinRow<V>(row.data(), n, 49, bb.data());
    ASSERT_EQ(ba, bb) << "row length " << n;
    for (int i = 0; i < n; ++i) {
      EXPECT_GE(bb[i], 0);
      EXPECT_LE(bb[i], 49);
    }
  }
  const GradientPixel edge[6] = {{0, 3, 4},       {0, 0, 0}, {0, 60, 80},
                                 {0, 0.3f, 0.4f}, {0, 0, 2}, {0, 0, 0}};
  std::int32_t bins[5];
  gradientMagnitudeBinRow<V>(edge, 5, 49, bins);
  EXPECT_EQ(bins[0], 5);
  EXPECT_EQ(bins[1], 0);
  EXPECT_EQ(bins[2], 49);  // 100, beyond the last bin
  EXPECT_EQ(bins[3], 0);
  EXPECT_EQ(bins[4], 2);
}

}  // namespace
}  // namespace simd
}  // namespace ldsm
