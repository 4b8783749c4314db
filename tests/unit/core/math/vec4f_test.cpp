// The four-float vector's operations, for the selected instruction set and the plain-C++ one,
// against per-lane scalar arithmetic.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "math/simd/vec4f.h"

namespace ldsm {
namespace simd {
namespace {

template <class V>
class Vec4fTest : public ::testing::Test {};
using VecTypes = ::testing::Types<Vec4, Vec4Scalar>;
TYPED_TEST_SUITE(Vec4fTest, VecTypes, );

template <class V>
void toArray(const V& v, float out[4]) {
  v.storeu(out);
}

TYPED_TEST(Vec4fTest, ArithmeticMatchesScalar) {
  using V = TypeParam;
  alignas(16) const float a[4] = {1.5f, -2.25f, 3.f, 1e-3f};
  alignas(16) const float b[4] = {0.5f, 4.f, -7.f, 9.f};
  float r[4];
  toArray(V::load(a) + V::load(b), r);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(r[i], a[i] + b[i]);
  toArray(V::load(a) - V::loadu(b), r);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(r[i], a[i] - b[i]);
  toArray(V::load(a) * V::set1(3.f), r);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(r[i], a[i] * 3.f);
  toArray(V::load(a) / V::load(b), r);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(r[i], a[i] / b[i], 1e-6f * std::fabs(a[i] / b[i]));
  toArray(squareRoot(absolute(V::load(a))), r);
  for (int i = 0; i < 4; ++i)
    EXPECT_NEAR(r[i], std::sqrt(std::fabs(a[i])), 1e-6f * std::sqrt(std::fabs(a[i])));
  toArray(squareRoot(V::zero()), r);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(r[i], 0.f);
}

TYPED_TEST(Vec4fTest, LoadInt16ConvertsEveryLaneExactlyFromAnUnalignedAddress) {
  using V = TypeParam;
  // One element in: an address 2 bytes past an 8-byte boundary, and the extremes of int16.
  alignas(16) const std::int16_t in[6] = {0, -32768, 32767, -1, 1234, -999};
  float r[4];
  toArray(V::loadInt16(in + 1), r);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(r[i], static_cast<float>(in[i + 1]));
}

TYPED_TEST(Vec4fTest, StoreInt16WritesEveryLaneExactlyToAnUnalignedAddress) {
  using V = TypeParam;
  const float in[4] = {-32768.f, 32767.f, -1.f, 1234.f};
  alignas(16) std::int16_t out[6] = {7, 7, 7, 7, 7, 7};
  V::loadu(in).storeInt16(out + 1);
  EXPECT_EQ(out[0], 7);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(out[i + 1], static_cast<std::int16_t>(in[i])) << i;
  EXPECT_EQ(out[5], 7);  // eight bytes written, no more
}

TYPED_TEST(Vec4fTest, MaximumOfEachPairOfLanes) {
  using V = TypeParam;
  const float a[4] = {1.f, -2.f, 0.f, 5.5f};
  const float b[4] = {0.5f, 3.f, -0.f, 5.5f};
  float r[4];
  toArray(maximum(V::loadu(a), V::loadu(b)), r);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(r[i], std::max(a[i], b[i])) << i;
}

TYPED_TEST(Vec4fTest, ComparisonsAndSelect) {
  using V = TypeParam;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float a[4] = {1.f, 2.f, nan, -1.f};
  const float b[4] = {1.f, 3.f, 0.f, -2.f};
  float r[4];
  toArray(select(V::loadu(a) < V::loadu(b), V::set1(1.f), V::zero()), r);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(r[i], a[i] < b[i] ? 1.f : 0.f) << i;
  toArray(select(V::loadu(a) >= V::loadu(b), V::set1(1.f), V::zero()), r);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(r[i], a[i] >= b[i] ? 1.f : 0.f) << i;
  toArray(select(V::loadu(a) > V::loadu(b), V::set1(1.f), V::zero()), r);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(r[i], a[i] > b[i] ? 1.f : 0.f) << i;
  EXPECT_TRUE(allOf(V::loadu(b) < V::set1(4.f)));
  EXPECT_FALSE(allOf(V::loadu(b) < V::set1(1.f)));
  EXPECT_FALSE(allOf(V::loadu(a) < V::set1(4.f)));  // NaN fails
  EXPECT_EQ(laneBits(V::loadu(b) < V::set1(4.f)), 0xF);
  EXPECT_EQ(laneBits(V::loadu(b) < V::set1(1.f)), 0b1100);
  EXPECT_EQ(laneBits(V::loadu(a) < V::set1(4.f)), 0b1011);  // NaN fails
  EXPECT_EQ(laneBits(V::loadu(b) > V::set1(9.f)), 0);
  EXPECT_FALSE(allOf((V::loadu(b) < V::set1(4.f)) & (V::loadu(b) > V::set1(-1.f))));
}

TYPED_TEST(Vec4fTest, LaneOperations) {
  using V = TypeParam;
  alignas(16) const float a[4] = {10.7f, 2.2f, 0.f, 7.99f};
  alignas(16) std::int32_t ints[4];
  float r[4];
  toArray(truncate(V::load(a), ints), r);
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(ints[i], static_cast<int>(a[i]));
    EXPECT_EQ(r[i], static_cast<float>(static_cast<int>(a[i])));
  }
  toArray(shiftDown1(V::load(a)), r);
  EXPECT_EQ(r[0], a[1]);
  EXPECT_EQ(r[1], a[2]);
  EXPECT_EQ(r[2], a[3]);
  EXPECT_EQ(r[3], 0.f);
  toArray(broadcast<0>(V::load(a)), r);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(r[i], a[0]);
  toArray(broadcast<3>(V::load(a)), r);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(r[i], a[3]);
  toArray(broadcast<2>(V::load(a)), r);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(r[i], a[2]);
  EXPECT_FLOAT_EQ(horizontalSum(V::load(a)), a[0] + a[1] + a[2] + a[3]);
}

TYPED_TEST(Vec4fTest, SetLanesPutsEachValueInItsLaneBitForBit) {
  using V = TypeParam;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float values[4] = {-0.f, 3.5e-39f, 1e30f, -7.25f};  // a denormal among them
  float r[4];
  toArray(V::setLanes(values[0], values[1], values[2], values[3]), r);
  EXPECT_EQ(std::memcmp(r, values, sizeof(values)), 0);
  toArray(V::setLanes(1.f, nan, 2.f, 3.f), r);
  EXPECT_EQ(r[0], 1.f);
  EXPECT_TRUE(std::isnan(r[1]));
  EXPECT_EQ(r[2], 2.f);
  EXPECT_EQ(r[3], 3.f);
}

TYPED_TEST(Vec4fTest, TransposeAndSum4) {
  using V = TypeParam;
  float m[4][4];
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) m[i][j] = static_cast<float>(10 * i + j);
  V a = V::loadu(m[0]), b = V::loadu(m[1]), c = V::loadu(m[2]), d = V::loadu(m[3]);
  const V s = sum4(a, b, c, d);
  transpose4(a, b, c, d);
  float rows[4][4];
  toArray(a, rows[0]);
  toArray(b, rows[1]);
  toArray(c, rows[2]);
  toArray(d, rows[3]);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) EXPECT_EQ(rows[i][j], m[j][i]) << i << "," << j;
  float sums[4];
  toArray(s, sums);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(sums[i], m[i][0] + m[i][1] + m[i][2] + m[i][3]);
}

}  // namespace
}  // namespace simd
}  // namespace ldsm
