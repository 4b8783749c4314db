// The coarse tracker's evaluation sums: blocks of four points added at once give the same bits
// as the same points added one by one (energy and Huber sums, counts, the inliers' rows), with
// every mix of points outside the frame, outliers and base outliers, and with the move of the
// float partial sums into double falling inside, at the edge of and outside the blocks.
#include "frontend/coarse_evaluation_sums.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

namespace ldsm {
namespace {

simd::CoarseWarp4 randomBlock(std::mt19937& rng, int inside) {
  std::uniform_real_distribution<float> U(-50.f, 50.f);
  simd::CoarseWarp4 b;
  for (int l = 0; l < 4; ++l) {
    b.dx_fx[l] = U(rng);
    b.dy_fy[l] = U(rng);
    b.nx[l] = U(rng) / 100.f;
    b.ny[l] = U(rng) / 100.f;
    b.iz[l] = U(rng) / 10.f;
    b.ref_term[l] = U(rng);
    b.residual[l] = U(rng);
  }
  b.inside = inside;
  return b;
}

simd::CoarseWeights4 randomWeights(std::mt19937& rng, int inlier, int base_outlier) {
  // Energies over several orders of magnitude, so that float rounding depends on the order.
  std::uniform_real_distribution<float> E(0.f, 1.f);
  std::uniform_int_distribution<int> exponent(-3, 4);
  simd::CoarseWeights4 w;
  for (int l = 0; l < 4; ++l) {
    w.energy[l] = E(rng) * std::pow(10.f, static_cast<float>(exponent(rng)));
    w.huber[l] = E(rng) * std::pow(10.f, static_cast<float>(exponent(rng)));
    w.weight[l] = E(rng);
  }
  w.inlier = inlier;
  w.base_outlier = base_outlier;
  return w;
}

WarpedResiduals rowsFor(std::size_t n) {
  WarpedResiduals r;
  r.allocate(n);
  return r;
}

void expectSameBits(float a, float b, const char* what, int i) {
  std::uint32_t x, y;
  std::memcpy(&x, &a, 4);
  std::memcpy(&y, &b, 4);
  ASSERT_EQ(x, y) << what << " of inlier " << i;
}

void expectSameSums(CoarseEvaluationSums& blocks, const WarpedResiduals& a,
                    CoarseEvaluationSums& points, const WarpedResiduals& b) {
  EXPECT_EQ(blocks.energy(), points.energy());
  EXPECT_EQ(blocks.huberSum(), points.huberSum());
  EXPECT_EQ(blocks.inImage(), points.inImage());
  EXPECT_EQ(blocks.inliers(), points.inliers());
  EXPECT_EQ(blocks.outliers(), points.outliers());
  EXPECT_EQ(blocks.baseOutliers(), points.baseOutliers());
  ASSERT_EQ(a.count, b.count);
  ASSERT_EQ(a.count, blocks.inliers());
  for (int i = 0; i < a.count; ++i) {
    expectSameBits(a.dx_fx[i], b.dx_fx[i], "dx_fx", i);
    expectSameBits(a.dy_fy[i], b.dy_fy[i], "dy_fy", i);
    expectSameBits(a.nx[i], b.nx[i], "nx", i);
    expectSameBits(a.ny[i], b.ny[i], "ny", i);
    expectSameBits(a.iz[i], b.iz[i], "iz", i);
    expectSameBits(a.ref_term[i], b.ref_term[i], "ref_term", i);
    expectSameBits(a.residual[i], b.residual[i], "residual", i);
    expectSameBits(a.weight[i], b.weight[i], "weight", i);
  }
}

/// Adds `blocks` blocks to both (one single point first when `offset`), by block and by point.
void runBoth(std::mt19937& rng, int blocks, bool offset, double full_share) {
  const std::size_t n = static_cast<std::size_t>(4 * blocks + 1);
  WarpedResiduals rows_a = rowsFor(n), rows_b = rowsFor(n);
  CoarseEvaluationSums by_block(rows_a), by_point(rows_b);
  std::uniform_real_distribution<double> coin(0.0, 1.0);
  std::uniform_int_distribution<int> mask(0, 15);
  if (offset) {  // shifts the moves into double from block edges into blocks
    const simd::CoarseWarp4 b = randomBlock(rng, 1);
    const simd::CoarseWeights4 w = randomWeights(rng, 1, 0);
    const simd::CoarseWarpedPoint p{b.dx_fx[0], b.dy_fy[0],    b.nx[0],      b.ny[0],
                                    b.iz[0],    b.ref_term[0], b.residual[0]};
    by_block.addPoint(p, {w.energy[0], w.huber[0], w.weight[0], true, false});
    by_point.addPoint(p, {w.energy[0], w.huber[0], w.weight[0], true, false});
  }
  int full_blocks = 0;
  for (int k = 0; k < blocks; ++k) {
    const bool full = coin(rng) < full_share;
    const int inside = full ? 0xF : mask(rng);
    const int inlier = full ? 0xF : mask(rng);
    const simd::CoarseWarp4 b = randomBlock(rng, inside);
    const simd::CoarseWeights4 w = randomWeights(rng, inlier, mask(rng));
    full_blocks += inside == 0xF && inlier == 0xF;
    by_block.addBlock(b, w);
    for (int l = 0; l < 4; ++l) {
      if (((inside >> l) & 1) == 0) continue;
      by_point.addPoint(
          {b.dx_fx[l], b.dy_fy[l], b.nx[l], b.ny[l], b.iz[l], b.ref_term[l], b.residual[l]},
          {w.energy[l], w.huber[l], w.weight[l], ((inlier >> l) & 1) != 0,
           ((w.base_outlier >> l) & 1) != 0});
    }
  }
  ASSERT_GT(full_blocks, blocks / 4);  // blocks of four inliers, the block path's kind
  by_block.finish();
  by_point.finish();
  expectSameSums(by_block, rows_a, by_point, rows_b);
}

TEST(CoarseEvaluationSums, BlocksOfFourInliersEqualTheSamePointsOneByOne) {
  std::mt19937 rng(7);
  runBoth(rng, 1000, false, 1.0);  // only full blocks: every move into double at a block edge
  runBoth(rng, 1000, true, 1.0);   // one point first: every move falls inside a block
}

TEST(CoarseEvaluationSums, MixedBlocksEqualTheSamePointsOneByOne) {
  std::mt19937 rng(11);
  for (int run = 0; run < 20; ++run) runBoth(rng, 700, run % 2 == 1, 0.7);
}

TEST(CoarseEvaluationSums, CountsInliersOutliersAndBaseOutliers) {
  WarpedResiduals rows = rowsFor(8);
  CoarseEvaluationSums sums(rows);
  std::mt19937 rng(3);
  // Lanes 0, 1, 3 inside; 0 and 3 inliers; base outliers 1 and 3 (an inlier can be one when
  // the threshold was doubled).
  sums.addBlock(randomBlock(rng, 0b1011), randomWeights(rng, 0b1001, 0b1010));
  sums.finish();
  EXPECT_EQ(sums.inImage(), 3);
  EXPECT_EQ(sums.inliers(), 2);
  EXPECT_EQ(sums.outliers(), 1);
  EXPECT_EQ(sums.baseOutliers(), 2);
  EXPECT_EQ(rows.count, 2);
}

}  // namespace
}  // namespace ldsm
