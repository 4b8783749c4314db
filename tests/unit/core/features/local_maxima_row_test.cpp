// The corner detector's row test for local maxima: the SIMD kernel (selected instruction set and
// plain C++) reports the same pixels in the same order as the per-pixel reference, on scores with
// plateaus (ties), zeros, NaN and a minimum score, for every row length.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include "features/local_maxima_row.h"

namespace ldsm {
namespace simd {
namespace {

template <class V>
class LocalMaximaRowTest : public ::testing::Test {};
using VecTypes = ::testing::Types<Vec4, Vec4Scalar>;
TYPED_TEST_SUITE(LocalMaximaRowTest, VecTypes, );

using Found = std::vector<std::pair<int, float>>;

TYPED_TEST(LocalMaximaRowTest, ReportsThePixelsOfTheReferenceInOrder) {
  using V = TypeParam;
  std::mt19937 rng(11);
  // Few distinct values: many ties, so plateaus and equal neighbours are common.
  std::uniform_int_distribution<int> level(0, 5);
  std::uniform_int_distribution<int> coin(0, 49);
  int reported = 0;
  for (int n = 3; n <= 45; ++n) {
    for (int round = 0; round < 40; ++round) {
      std::vector<float> rows[3];
      for (auto& r : rows) {
        r.resize(static_cast<std::size_t>(n));
        for (float& v : r) {
          v = 0.5f * static_cast<float>(level(rng)) - 0.5f;  // -0.5 .. 2
          if (coin(rng) == 0) v = std::numeric_limits<float>::quiet_NaN();
        }
      }
      const float min_score = round % 3 == 0 ? 0.f : 1.f;
      Found expected, got;
      reference::localMaximaRow(rows[0].data(), rows[1].data(), rows[2].data(), 1, n - 1, min_score,
                                [&](int x, float v) { expected.emplace_back(x, v); });
      localMaximaRow<V>(rows[0].data(), rows[1].data(), rows[2].data(), 1, n - 1, min_score,
                        [&](int x, float v) { got.emplace_back(x, v); });
      ASSERT_EQ(got, expected) << "row length " << n << ", round " << round;
      reported += static_cast<int>(got.size());
    }
  }
  EXPECT_GT(reported, 1000);  // the rows do have maxima
}

TEST(LocalMaximaRow, OnePixelOfAPlateauSurvivesAndNaNNever) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<float> above = {0, 0, 0, 0, 0, 0, 0, 0};
  const std::vector<float> row = {0, 2, 2, 1, nan, 0, 3, 0};
  const std::vector<float> below = {0, 0, 0, 0, 0, 0, 0, 0};
  Found got;
  reference::localMaximaRow(above.data(), row.data(), below.data(), 1, 7, 0.f,
                            [&](int x, float v) { got.emplace_back(x, v); });
  EXPECT_EQ(got, (Found{{1, 2.f}, {6, 3.f}}));
  got.clear();
  reference::localMaximaRow(above.data(), row.data(), below.data(), 1, 7, 2.5f,
                            [&](int x, float v) { got.emplace_back(x, v); });
  EXPECT_EQ(got, (Found{{6, 3.f}}));
}

}  // namespace
}  // namespace simd
}  // namespace ldsm
