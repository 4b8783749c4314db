// The saturation mask of a row: the SIMD kernel (selected instruction set and plain C++) against
// the per-pixel reference, for every row width, values at and around the level, NaN and
// infinities, and with the byte after the row untouched.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "image/threshold_row.h"

namespace ldsm {
namespace simd {
namespace {

template <class V>
class ThresholdRowTest : public ::testing::Test {};
using VecTypes = ::testing::Types<Vec4, Vec4Scalar>;
TYPED_TEST_SUITE(ThresholdRowTest, VecTypes, );

TYPED_TEST(ThresholdRowTest, EqualsThePerPixelMaskForEveryWidth) {
  using V = TypeParam;
  const float level = 250.f;
  const float special[] = {level,
                           std::nextafter(level, 0.f),
                           std::nextafter(level, 1e9f),
                           std::numeric_limits<float>::quiet_NaN(),
                           std::numeric_limits<float>::infinity(),
                           -std::numeric_limits<float>::infinity(),
                           255.f,
                           0.f};
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> pick(0, 15);
  std::uniform_real_distribution<float> grey(0.f, 255.f);
  int marked = 0;
  for (int w = 0; w <= 41; ++w) {
    std::vector<float> in(static_cast<std::size_t>(w));
    for (float& v : in) {
      const int k = pick(rng);
      v = k < 8 ? special[k] : grey(rng);
    }
    std::vector<std::uint8_t> a(in.size() + 1, 7), b(in.size() + 1, 7);
    reference::markAtLeastRow(in.data(), w, level, a.data());
    markAtLeastRow<V>(in.data(), w, level, b.data());
    for (int x = 0; x < w; ++x) {
      const auto i = static_cast<std::size_t>(x);
      ASSERT_EQ(a[i], in[i] >= level ? 1 : 0) << "reference, width " << w << ", pixel " << x;
      ASSERT_EQ(b[i], a[i]) << "width " << w << ", pixel " << x << ", value " << in[i];
      marked += b[i];
    }
    EXPECT_EQ(b[in.size()], 7) << "written past the row of width " << w;
  }
  EXPECT_GT(marked, 50);  // the inputs reach both sides of the level
}

}  // namespace
}  // namespace simd
}  // namespace ldsm
