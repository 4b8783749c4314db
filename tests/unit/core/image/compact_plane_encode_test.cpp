// The 16-bit plane encoder's two passes: the SIMD kernels (selected instruction set and plain C++)
// against the per-value reference, bit for bit: the int16 values (ties to even at exact half
// steps, both signs, the int16 extremes), the largest magnitude, and non-finite values found in
// any position, for every row length.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "image/compact_plane_encode.h"

namespace ldsm {
namespace simd {
namespace {

template <class V>
class CompactPlaneEncodeTest : public ::testing::Test {};
using VecTypes = ::testing::Types<Vec4, Vec4Scalar>;
TYPED_TEST_SUITE(CompactPlaneEncodeTest, VecTypes, );

TYPED_TEST(CompactPlaneEncodeTest, QuantizedValuesEqualTheReference) {
  using V = TypeParam;
  std::mt19937 rng(4);
  const float step = 1.f / 128.f, inv_step = 128.f;
  std::uniform_real_distribution<float> value(-255.f, 255.f);
  std::uniform_int_distribution<int> stored(-32767, 32767);
  std::uniform_int_distribution<int> kind(0, 3);
  int ties = 0;
  for (int n = 0; n <= 45; ++n) {
    std::vector<float> in(static_cast<std::size_t>(n));
    for (float& v : in) {
      switch (kind(rng)) {
        case 0:  // an exact half step: rounds to the even neighbour
          v = (static_cast<float>(stored(rng)) + 0.5f) * step;
          if (v / step > 32766.f || v / step < -32767.f) v = 0.f;
          ++ties;
          break;
        case 1:
          v = static_cast<float>(stored(rng)) * step;
          break;
        default:
          v = value(rng);
      }
    }
    if (n >= 2) {
      in[0] = 32767.f * step;
      in[1] = -32767.f * step;
    }
    std::vector<std::int16_t> expected(in.size(), 7), got(in.size(), 7);
    reference::quantizeRow(in.data(), n, inv_step, expected.data());
    quantizeRow<V>(in.data(), n, inv_step, got.data());
    ASSERT_EQ(got, expected) << "row length " << n;
    for (int i = 0; i < n; ++i) EXPECT_NEAR(got[i] * step, in[i], 0.5f * step);
  }
  EXPECT_GT(ties, 100);
  // Ties to even, both signs.
  const float halves[4] = {0.5f * step, 1.5f * step, -0.5f * step, -2.5f * step};
  std::int16_t q[4];
  quantizeRow<V>(halves, 4, inv_step, q);
  EXPECT_EQ(q[0], 0);
  EXPECT_EQ(q[1], 2);
  EXPECT_EQ(q[2], 0);
  EXPECT_EQ(q[3], -2);
}

TYPED_TEST(CompactPlaneEncodeTest, RangeEqualsTheReferenceAndFindsNonFiniteValues) {
  using V = TypeParam;
  std::mt19937 rng(8);
  std::uniform_real_distribution<float> value(-300.f, 300.f);
  const float specials[3] = {std::numeric_limits<float>::quiet_NaN(),
                             std::numeric_limits<float>::infinity(),
                             -std::numeric_limits<float>::infinity()};
  for (int n = 0; n <= 45; ++n) {
    std::vector<float> in(static_cast<std::size_t>(n));
    for (float& v : in) v = value(rng);
    PlaneRange expected, got;
    reference::addToRange(in.data(), n, expected);
    addToRange<V>(in.data(), n, got);
    ASSERT_TRUE(got.finite());
    ASSERT_EQ(got.max_abs, expected.max_abs) << "row length " << n;
    // Two rows accumulate into one range.
    addToRange<V>(in.data(), n, got);
    EXPECT_EQ(got.max_abs, expected.max_abs);
    for (int at = 0; at < n; ++at) {
      for (const float s : specials) {
        std::vector<float> bad = in;
        bad[static_cast<std::size_t>(at)] = s;
        PlaneRange r;
        addToRange<V>(bad.data(), n, r);
        EXPECT_FALSE(r.finite()) << "value " << s << " at " << at << " of " << n;
      }
    }
  }
}

}  // namespace
}  // namespace simd
}  // namespace ldsm
