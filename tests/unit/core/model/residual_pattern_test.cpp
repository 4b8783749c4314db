// The residual pattern (model/residual_pattern.h): DSO's 8 samples spread over a 5x5
// neighbourhood, each a distinct pixel within kPatternPadding of the point.
#include "model/residual_pattern.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <set>
#include <utility>

#include "model/patch_point.h"

namespace ldsm {
namespace {

std::set<std::pair<int, int>> offsets() {
  std::set<std::pair<int, int>> s;
  for (const auto& o : kPatternOffsets) s.insert({o[0], o[1]});
  return s;
}

TEST(ResidualPattern, HasEightDistinctOffsetsIncludingThePointItself) {
  static_assert(kPatternSize == 8, "DSO's pattern 8");
  const std::set<std::pair<int, int>> s = offsets();
  EXPECT_EQ(s.size(), static_cast<std::size_t>(kPatternSize));
  EXPECT_EQ(s.count({0, 0}), 1u);
}

TEST(ResidualPattern, OffsetsStayWithinThePaddingAndSpanIt) {
  int max_abs = 0, min_x = 0, max_x = 0, min_y = 0, max_y = 0;
  for (const auto& o : kPatternOffsets) {
    max_abs = std::max({max_abs, std::abs(o[0]), std::abs(o[1])});
    EXPECT_LE(std::abs(o[0]) + std::abs(o[1]), 2) << o[0] << ", " << o[1];
    min_x = std::min(min_x, o[0]);
    max_x = std::max(max_x, o[0]);
    min_y = std::min(min_y, o[1]);
    max_y = std::max(max_y, o[1]);
  }
  // kPatternPadding is the largest |offset| (image borders are kept by it), and the pattern
  // reaches it on every side: it covers the 5x5 neighbourhood.
  EXPECT_EQ(max_abs, kPatternPadding);
  EXPECT_EQ(min_x, -kPatternPadding);
  EXPECT_EQ(max_x, kPatternPadding);
  EXPECT_EQ(min_y, -kPatternPadding);
  EXPECT_EQ(max_y, kPatternPadding);
}

TEST(ResidualPattern, IsSymmetricAboutTheMainDiagonal) {
  // DSO's pattern: mirrored in x = y (dx <-> dy), but not point-symmetric ((-1, -1) without
  // (1, 1)), so a sample at (dx, dy) has its partner at (dy, dx).
  const std::set<std::pair<int, int>> s = offsets();
  for (const auto& [dx, dy] : s) EXPECT_EQ(s.count({dy, dx}), 1u) << dx << ", " << dy;
  EXPECT_EQ(s.count({-1, -1}), 1u);
  EXPECT_EQ(s.count({1, 1}), 0u);
}

TEST(ResidualPattern, APatchPointStoresOneColourAndWeightPerSample) {
  const PatchPoint p;
  EXPECT_EQ(sizeof(p.colors) / sizeof(p.colors[0]), static_cast<std::size_t>(kPatternSize));
  EXPECT_EQ(sizeof(p.grad_weights) / sizeof(p.grad_weights[0]),
            static_cast<std::size_t>(kPatternSize));
}

}  // namespace
}  // namespace ldsm
