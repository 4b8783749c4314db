// The rectifier's row remap: the SIMD kernel (selected instruction set and plain C++) against the
// per-pixel reference, bit for bit, for 8-bit and float images, with pixels without input, at the
// last column and row (the clamped 2x2 block) and every tail length; and the separable row remap
// against the general one.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "camera/remap_bilinear.h"
#include "ldsm/image.h"

namespace ldsm {
namespace simd {
namespace {

template <class V>
class RemapBilinearTest : public ::testing::Test {};
using VecTypes = ::testing::Types<Vec4, Vec4Scalar>;
TYPED_TEST_SUITE(RemapBilinearTest, VecTypes, );

template <typename T>
RemapInput<T> input(const Image<T>& img) {
  return {img.view().data, img.view().stride, img.width(), img.height()};
}

/// A 53x37 8-bit and a float input of random content.
struct RandomImages {
  Image<std::uint8_t> bytes{53, 37};
  Image<float> floats{53, 37};
};
RandomImages randomImages(std::mt19937& rng) {
  RandomImages out;
  std::uniform_int_distribution<int> B(0, 255);
  for (int y = 0; y < 37; ++y)
    for (int x = 0; x < 53; ++x) {
      out.bytes(x, y) = static_cast<std::uint8_t>(B(rng));
      out.floats(x, y) = 0.37f * static_cast<float>(B(rng)) - 11.f;
    }
  return out;
}

template <class V, typename T>
void expectRowsAgree(const Image<T>& img, std::mt19937& rng) {
  std::uniform_real_distribution<float> X(0.f, static_cast<float>(img.width() - 1));
  std::uniform_real_distribution<float> Y(0.f, static_cast<float>(img.height() - 1));
  std::uniform_int_distribution<int> coin(0, 9);
  for (int width = 0; width <= 41; ++width) {
    std::vector<float> mx(width), my(width), a(width, 7.f), b(width, 7.f);
    for (int u = 0; u < width; ++u) {
      mx[u] = X(rng);
      my[u] = Y(rng);
      // A pixel without input has both coordinates -1 (the table's contract): the last column
      // or row is not set on it, which would leave a valid x with y = -1 (a read before the
      // image).
      const bool no_input = coin(rng) == 0;
      const bool last_column = coin(rng) == 1, last_row = coin(rng) == 2;
      if (no_input) {
        mx[u] = my[u] = -1.f;
      } else {
        if (last_column) mx[u] = static_cast<float>(img.width() - 1);
        if (last_row) my[u] = static_cast<float>(img.height() - 1);
      }
    }
    reference::remapRow(input(img), mx.data(), my.data(), width, -3.f, a.data());
    remapRow<V>(input(img), mx.data(), my.data(), width, -3.f, b.data());
    for (int u = 0; u < width; ++u) {
      ASSERT_EQ(a[u], b[u]) << "width " << width << " pixel " << u;
      if (mx[u] < 0.f) {
        EXPECT_EQ(b[u], -3.f);
      }
    }
  }
}

// A separable table's row (one input row for the output row, the columns' cells and weights
// precomputed): bit for bit the general remap of that row with the row's y repeated, in the
// reference and the SIMD kernel, with columns without input and the last row and column.
template <class V, typename T>
void expectSeparableRowsAgree(const Image<T>& img, std::mt19937& rng) {
  std::uniform_real_distribution<float> X(0.f, static_cast<float>(img.width() - 1));
  std::uniform_real_distribution<float> Y(0.f, static_cast<float>(img.height() - 1));
  std::uniform_int_distribution<int> coin(0, 9);
  for (int width = 0; width <= 41; ++width) {
    std::vector<float> mx(width), a(width, 7.f), b(width, 7.f), c(width, 7.f);
    for (int u = 0; u < width; ++u) {
      mx[u] = X(rng);
      if (coin(rng) == 0) mx[u] = -1.f;                                 // sees no input
      if (coin(rng) == 1) mx[u] = static_cast<float>(img.width() - 1);  // last column
    }
    const float y = coin(rng) == 2 ? static_cast<float>(img.height() - 1) : Y(rng);
    const std::vector<float> my(width, y);
    const SeparableColumns cols = separableColumns(mx, img.width());
    std::int32_t y0;
    float ay;
    clampedCell(y, img.height(), y0, ay);
    reference::remapRow(input(img), mx.data(), my.data(), width, -3.f, a.data());
    reference::remapSeparableRow(input(img), cols.x0.data(), cols.ax.data(), y0, ay, width, -3.f,
                                 b.data());
    remapSeparableRow<V>(input(img), cols.x0.data(), cols.ax.data(), y0, ay, width, -3.f, c.data());
    for (int u = 0; u < width; ++u) {
      ASSERT_EQ(a[u], b[u]) << "width " << width << " pixel " << u;
      ASSERT_EQ(a[u], c[u]) << "width " << width << " pixel " << u;
    }
  }
}

TYPED_TEST(RemapBilinearTest, ASeparableRowEqualsTheGeneralRemapOfThatRow) {
  using V = TypeParam;
  std::mt19937 rng(9);
  const RandomImages img = randomImages(rng);
  expectSeparableRowsAgree<V>(img.bytes, rng);
  expectSeparableRowsAgree<V>(img.floats, rng);
  // One-pixel-wide and one-pixel-high inputs (the 2x2 block degenerates).
  Image<std::uint8_t> column(1, 5), row(6, 1);
  for (int y = 0; y < 5; ++y) column(0, y) = static_cast<std::uint8_t>(10 * y);
  for (int x = 0; x < 6; ++x) row(x, 0) = static_cast<std::uint8_t>(7 * x);
  expectSeparableRowsAgree<V>(column, rng);
  expectSeparableRowsAgree<V>(row, rng);
}

TYPED_TEST(RemapBilinearTest, FourPixelsAtOnceEqualThePixelByPixelRemap) {
  using V = TypeParam;
  std::mt19937 rng(5);
  const RandomImages img = randomImages(rng);
  expectRowsAgree<V>(img.bytes, rng);
  expectRowsAgree<V>(img.floats, rng);
  // One-pixel-wide and one-pixel-high inputs (the 2x2 block degenerates; on SSE2 and NEON the
  // 8-bit blend then loads lane by lane).
  Image<std::uint8_t> column(1, 5), row(6, 1);
  for (int y = 0; y < 5; ++y) column(0, y) = static_cast<std::uint8_t>(10 * y + 3);
  for (int x = 0; x < 6; ++x) row(x, 0) = static_cast<std::uint8_t>(7 * x + 1);
  expectRowsAgree<V>(column, rng);
  expectRowsAgree<V>(row, rng);
}

TEST(RemapBilinear, ReferenceInterpolatesAndClampsAtTheLastPixel) {
  Image<float> img(4, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 4; ++x) img(x, y) = static_cast<float>(10 * y + x);
  // A linear image is reproduced exactly, also on the last column and row (clamped block).
  const float mx[4] = {1.25f, 3.f, 0.5f, -1.f}, my[4] = {0.5f, 2.f, 2.f, -1.f};
  float out[4];
  reference::remapRow(input(img), mx, my, 4, -1.f, out);
  EXPECT_FLOAT_EQ(out[0], 6.25f);
  EXPECT_FLOAT_EQ(out[1], 23.f);
  EXPECT_FLOAT_EQ(out[2], 20.5f);
  EXPECT_EQ(out[3], -1.f);
}

}  // namespace
}  // namespace simd
}  // namespace ldsm
