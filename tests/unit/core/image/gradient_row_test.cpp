// A pyramid row's packed (intensity, dx, dy): the SIMD kernel (selected instruction set and plain
// C++) against the per-pixel reference, bit for bit, for every row width, on the border rows
// (no row above or below) and with the pixel after the row untouched.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

#include "image/gradient_row.h"

namespace ldsm {
namespace simd {
namespace {

template <class V>
class GradientRowTest : public ::testing::Test {};
using VecTypes = ::testing::Types<Vec4, Vec4Scalar>;
TYPED_TEST_SUITE(GradientRowTest, VecTypes, );

bool sameBits(const GradientPixel& a, const GradientPixel& b) {
  return std::memcmp(&a, &b, sizeof(GradientPixel)) == 0;
}

TYPED_TEST(GradientRowTest, EqualsThePerPixelRowBitForBit) {
  using V = TypeParam;
  std::mt19937 rng(6);
  std::uniform_real_distribution<float> grey(0.f, 255.f);
  for (int w = 0; w <= 37; ++w) {
    std::vector<float> up(static_cast<std::size_t>(w)), row(up.size()), down(up.size());
    for (std::size_t i = 0; i < up.size(); ++i) {
      up[i] = grey(rng);
      row[i] = grey(rng);
      down[i] = grey(rng);
    }
    for (const bool border : {false, true}) {
      const GradientPixel sentinel{-7.f, -7.f, -7.f};
      std::vector<GradientPixel> a(up.size() + 1, sentinel), b(up.size() + 1, sentinel);
      reference::gradientRow(border ? nullptr : up.data(), row.data(),
                             border ? nullptr : down.data(), w, a.data());
      gradientRow<V>(border ? nullptr : up.data(), row.data(), border ? nullptr : down.data(), w,
                     b.data());
      for (int x = 0; x <= w; ++x)
        ASSERT_TRUE(sameBits(a[static_cast<std::size_t>(x)], b[static_cast<std::size_t>(x)]))
            << "width " << w << (border ? " (border row)" : "") << ", pixel " << x;
      EXPECT_TRUE(sameBits(b[static_cast<std::size_t>(w)], sentinel)) << "written past the row";
    }
  }
}

}  // namespace
}  // namespace simd
}  // namespace ldsm
