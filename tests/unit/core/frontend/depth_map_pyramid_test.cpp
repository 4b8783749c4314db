// Sparse inverse-depth maps over the pyramid: splatting, weighted 2x2 averaging, dilation, the
// extracted point lists and bad input.
#include "frontend/depth_map_pyramid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "ldsm/error.h"

namespace ldsm {
namespace {

constexpr int kW = 64;
constexpr int kH = 48;
constexpr int kLevels = 4;

// A reference pyramid whose intensity encodes the pixel position, so extracted intensities can be
// checked.
ImagePyramid makeReference() {
  ImageF image(kW, kH);
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) image(x, y) = static_cast<float>(x + 100 * y);
  }
  ImagePyramid pyramid(kW, kH, kLevels);
  pyramid.build(image.view());
  return pyramid;
}

// Inverse depth of a plane, affine in the level-0 pixel coordinates.
float planeIdepth(float u, float v) {
  return 0.2f + 0.001f * u - 0.0005f * v;
}

TEST(DepthMapPyramidTest, SplatsToNearestPixelWithWeightedAverage) {
  const ImagePyramid ref = makeReference();
  DepthMapPyramid maps(kW, kH, kLevels);
  const std::vector<DepthPoint> points = {{10.3f, 20.6f, 0.5f, 1.f},
                                          {9.6f, 21.4f, 0.2f, 3.f},   // same pixel (10, 21)
                                          {30.f, 30.f, 0.25f, 1.f}};  // a second pixel
  EXPECT_EQ(maps.build(points.data(), points.size(), ref), 3);
  EXPECT_EQ(maps.rejectedPoints(), 0);
  EXPECT_NEAR(maps.idepthAt(0, 10, 21), (0.5f * 1 + 0.2f * 3) / 4, 1e-6);
  EXPECT_NEAR(maps.idepthAt(0, 30, 30), 0.25f, 1e-6);
  EXPECT_EQ(maps.idepthAt(0, 10, 20), 0.f);
}

// A map keyframe's points (brought back into the window, seen from elsewhere) and the window's at
// one pixel on both sides of a depth discontinuity: the nearer surface, whatever the order. The
// window's points among themselves are averaged as before, however far apart.
TEST(DepthMapPyramidTest, KeepsTheNearerOfTheMapsAndTheWindowsSurfaceAtAPixel) {
  const ImagePyramid ref = makeReference();
  DepthMapPyramid maps(kW, kH, kLevels);  // discontinuity factor 1.25
  const std::vector<DepthPoint> hidden_map = {{10.f, 20.f, 0.5f, 1.f, false},
                                              {10.f, 20.f, 0.52f, 3.f, false},
                                              {10.f, 20.f, 0.2f, 9.f, true}};  // behind: hidden
  EXPECT_EQ(maps.build(hidden_map.data(), hidden_map.size(), ref), 3);
  EXPECT_NEAR(maps.idepthAt(0, 10, 20), (0.5f + 3 * 0.52f) / 4, 1e-6);
  const std::vector<DepthPoint> map_in_front = {{10.f, 20.f, 0.2f, 1.f, false},
                                                {10.f, 20.f, 0.5f, 1.f, true},     // hides it
                                                {10.f, 20.f, 0.52f, 3.f, true},    // same surface
                                                {10.f, 20.f, 0.21f, 5.f, false}};  // hidden
  maps.build(map_in_front.data(), map_in_front.size(), ref);
  EXPECT_NEAR(maps.idepthAt(0, 10, 20), (0.5f + 3 * 0.52f) / 4, 1e-6);
  // Within the factor: one surface, averaged.
  const std::vector<DepthPoint> close = {{10.f, 20.f, 0.5f, 1.f, false},
                                         {10.f, 20.f, 0.41f, 1.f, true}};
  maps.build(close.data(), close.size(), ref);
  EXPECT_NEAR(maps.idepthAt(0, 10, 20), 0.455f, 1e-6);
  // The window's own points: averaged even across the factor (as the first test).
  const std::vector<DepthPoint> window = {{10.f, 20.f, 0.5f, 1.f, false},
                                          {10.f, 20.f, 0.2f, 1.f, false}};
  maps.build(window.data(), window.size(), ref);
  EXPECT_NEAR(maps.idepthAt(0, 10, 20), 0.35f, 1e-6);
  EXPECT_EQ(maps.points(0).count, 1 + 4);  // the pixel and its diagonal fills
}

TEST(DepthMapPyramidTest, CoarseLevelsAverageChildrenExactlyForAPlane) {
  const ImagePyramid ref = makeReference();
  std::vector<DepthPoint> dense;
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      dense.push_back({static_cast<float>(x), static_cast<float>(y),
                       planeIdepth(static_cast<float>(x), static_cast<float>(y)), 1.f});
    }
  }
  DepthMapPyramid maps(kW, kH, kLevels);
  maps.build(dense.data(), dense.size(), ref);
  for (int l = 0; l < kLevels; ++l) {
    const LevelPoints& pts = maps.points(l);
    ASSERT_EQ(pts.count, maps.width(l) * maps.height(l)) << "level " << l;
    const float s = static_cast<float>(1 << l);
    for (int i = 0; i < pts.count; ++i) {
      // Pixel centre of a level-l pixel in level-0 coordinates.
      const float u0 = (pts.x[i] + 0.5f) * s - 0.5f;
      const float v0 = (pts.y[i] + 0.5f) * s - 0.5f;
      ASSERT_NEAR(pts.idepth[i], planeIdepth(u0, v0), 1e-5) << "level " << l;
      ASSERT_FLOAT_EQ(
          pts.intensity[i],
          ref.gradients(l)(static_cast<int>(pts.x[i]), static_cast<int>(pts.y[i])).intensity);
    }
  }
}

TEST(DepthMapPyramidTest, DilatesDiagonallyOnFineLevelsAndCrosswiseOnCoarse) {
  const ImagePyramid ref = makeReference();
  DepthMapPyramid maps(kW, kH, kLevels);
  // One point at level-0 pixel (20, 20): level 2 pixel (5, 5) holds it.
  const std::vector<DepthPoint> points = {{20.f, 20.f, 0.4f, 2.f}};
  maps.build(points.data(), points.size(), ref);
  EXPECT_EQ(maps.points(0).count, 5);  // itself + 4 diagonal neighbours
  for (const auto& d : {std::pair{1, 1}, {-1, 1}, {1, -1}, {-1, -1}}) {
    EXPECT_NEAR(maps.idepthAt(0, 20 + d.first, 20 + d.second), 0.4f, 1e-6);
  }
  EXPECT_EQ(maps.idepthAt(0, 21, 20), 0.f);
  EXPECT_EQ(maps.idepthAt(0, 22, 22), 0.f);  // one dilation step only
  EXPECT_EQ(maps.points(2).count, 5);        // itself + 4 cross neighbours
  EXPECT_NEAR(maps.idepthAt(2, 6, 5), 0.4f, 1e-6);
  EXPECT_NEAR(maps.idepthAt(2, 5, 4), 0.4f, 1e-6);
  EXPECT_EQ(maps.idepthAt(2, 6, 6), 0.f);
}

TEST(DepthMapPyramidTest, DilationAveragesNeighboursButNotAcrossDiscontinuities) {
  const ImagePyramid ref = makeReference();
  DepthMapPyramid maps(kW, kH, kLevels);
  // Pixel (11, 11) has diagonal neighbours (10, 10) and (12, 12) with similar depth: averaged
  // with their weights. Pixel (31, 11) has neighbours at 0.2 and 0.5: left empty.
  const std::vector<DepthPoint> points = {{10.f, 10.f, 0.30f, 1.f},
                                          {12.f, 12.f, 0.33f, 2.f},
                                          {30.f, 10.f, 0.2f, 1.f},
                                          {32.f, 12.f, 0.5f, 1.f}};
  maps.build(points.data(), points.size(), ref);
  EXPECT_NEAR(maps.idepthAt(0, 11, 11), (0.30f + 2 * 0.33f) / 3, 1e-6);
  EXPECT_EQ(maps.idepthAt(0, 31, 11), 0.f);
  EXPECT_NEAR(maps.idepthAt(0, 29, 9), 0.2f, 1e-6);  // single-neighbour fill still happens
}

TEST(DepthMapPyramidTest, RebuildForgetsThePreviousPoints) {
  const ImagePyramid ref = makeReference();
  DepthMapPyramid maps(kW, kH, kLevels);
  const std::vector<DepthPoint> a = {{20.f, 20.f, 0.4f, 1.f}};
  const std::vector<DepthPoint> b = {{40.f, 30.f, 0.3f, 1.f}};
  maps.build(a.data(), a.size(), ref);
  maps.build(b.data(), b.size(), ref);
  EXPECT_EQ(maps.idepthAt(0, 20, 20), 0.f);
  EXPECT_NEAR(maps.idepthAt(0, 40, 30), 0.3f, 1e-6);
  EXPECT_EQ(maps.points(0).count, 5);
}

TEST(DepthMapPyramidTest, SkipsInvalidPoints) {
  const ImagePyramid ref = makeReference();
  DepthMapPyramid maps(kW, kH, kLevels);
  const float nan = std::nanf("");
  const std::vector<DepthPoint> points = {
      {-0.6f, 5.f, 0.3f, 1.f},             // left of the image
      {5.f, kH - 0.4f, 0.3f, 1.f},         // below
      {nan, 5.f, 0.3f, 1.f},               // NaN position
      {5.f, 5.f, nan, 1.f},                // NaN inverse depth
      {5.f, 5.f, 0.f, 1.f},                // zero inverse depth
      {5.f, 5.f, -1.f, 1.f},               // negative inverse depth
      {5.f, 5.f, 0.3f, 0.f},               // zero weight
      {5.f, 5.f, 0.3f, INFINITY},          // infinite weight
      {kW - 0.6f, kH - 0.6f, 0.3f, 1.f}};  // valid, rounds to the last pixel
  EXPECT_EQ(maps.build(points.data(), points.size(), ref), 1);
  EXPECT_EQ(maps.rejectedPoints(), 8);
  EXPECT_NEAR(maps.idepthAt(0, kW - 1, kH - 1), 0.3f, 1e-6);
}

TEST(DepthMapPyramidTest, RejectsBadSizes) {
  EXPECT_THROW(DepthMapPyramid(0, 10, 1), InputError);
  EXPECT_THROW(DepthMapPyramid(64, 48, 0), ConfigError);
  EXPECT_THROW(DepthMapPyramid(64, 48, 8), ConfigError);
  DepthMapPyramid maps(kW, kH, kLevels);
  ImageF other(kW * 2, kH, 0.f);
  ImagePyramid wrong_size(kW * 2, kH, kLevels);
  wrong_size.build(other.view());
  EXPECT_THROW(maps.build(nullptr, 0, wrong_size), InputError);
  ImageF same(kW, kH, 0.f);
  ImagePyramid too_few_levels(kW, kH, 2);
  too_few_levels.build(same.view());
  EXPECT_THROW(maps.build(nullptr, 0, too_few_levels), InputError);
}

void expectSamePoints(const DepthMapPyramid& a, const DepthMapPyramid& b) {
  for (int l = 0; l < kLevels; ++l) {
    const LevelPoints& pa = a.points(l);
    const LevelPoints& pb = b.points(l);
    ASSERT_EQ(pa.count, pb.count) << "level " << l;
    for (int i = 0; i < pa.count; ++i) {
      EXPECT_EQ(pa.x[i], pb.x[i]);
      EXPECT_EQ(pa.y[i], pb.y[i]);
      EXPECT_EQ(pa.idepth[i], pb.idepth[i]);
      EXPECT_EQ(pa.intensity[i], pb.intensity[i]);
      EXPECT_EQ(pa.grad_sq[i], pb.grad_sq[i]);
    }
  }
}

// Pyramids built one after another into one canvas (as the mapping stage builds every tracking
// reference) get the point lists of their own canvases, bit for bit, whatever the canvas held
// before; they hold no dense planes themselves.
TEST(DepthMapPyramidTest, PyramidsSharingACanvasGetTheirOwnCanvasesPoints) {
  const ImagePyramid ref = makeReference();
  std::vector<DepthPoint> a, b;
  for (int i = 0; i < 300; ++i) {
    const float u = static_cast<float>((i * 37) % kW) + 0.3f;
    const float v = static_cast<float>((i * 11) % kH) + 0.6f;
    a.push_back({u, v, planeIdepth(u, v), 1.f + static_cast<float>(i % 3), i % 5 == 0});
    b.push_back({v, u * 0.7f, 0.5f * planeIdepth(v, u), 2.f, i % 7 == 0});
  }
  DepthMapCanvas canvas(kW, kH, kLevels);
  DepthMapPyramid shared_a(kW, kH, kLevels), shared_b(kW, kH, kLevels);
  DepthMapPyramid own_a(kW, kH, kLevels), own_b(kW, kH, kLevels);
  own_a.build(a.data(), a.size(), ref);
  own_b.build(b.data(), b.size(), ref);
  for (int round = 0; round < 2; ++round) {  // each also after the other's build
    shared_a.build(a.data(), a.size(), ref, canvas);
    expectSamePoints(shared_a, own_a);
    shared_b.build(b.data(), b.size(), ref, canvas);
    expectSamePoints(shared_b, own_b);
  }
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) ASSERT_EQ(canvas.idepthAt(0, x, y), own_b.idepthAt(0, x, y));
  // The same point lists; the own canvas's cells (at least a sum and a weight per splatted
  // point's pixel) only in the pyramid that has one.
  EXPECT_GE(own_a.bytes(), shared_a.bytes() + 2 * sizeof(float) * a.size());
  EXPECT_GE(canvas.bytes(), 2 * sizeof(float) * b.size());
}

void expectDensePlanesResults(const std::vector<DepthPoint>& points, const ImagePyramid& ref, int w,
                              int h, int levels, int memory_fraction);

// The canvas keeps cells for the pixels that have sums alone: the results are those of dense
// planes (as the canvas had them before), bit for bit, in a fraction of their memory.
TEST(DepthMapPyramidTest, MatchesDensePlanesBitForBitInAFractionOfTheirMemory) {
  constexpr int w = 1232, h = 368, levels = 5;
  ImageF image(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) image(x, y) = static_cast<float>((x * 7 + y * 13) % 251);
  ImagePyramid ref(w, h, levels);
  ref.build(image.view());
  for (const int count : {3000, 12000}) {
    SCOPED_TRACE(count);
    std::mt19937 rng(static_cast<unsigned>(count));
    std::uniform_real_distribution<float> u(-2.f, w + 1.f), v(-2.f, h + 1.f), d(0.05f, 2.f);
    std::vector<DepthPoint> points;
    for (int i = 0; i < count; ++i)  // a window's points, a few clustered at one pixel
      points.push_back({i % 50 == 0 ? 600.2f : u(rng), i % 50 == 0 ? 200.4f : v(rng), d(rng),
                        0.5f + d(rng), i % 9 == 0});
    expectDensePlanesResults(points, ref, w, h, levels, count == 3000 ? 2 : 1);
  }
}

void expectDensePlanesResults(const std::vector<DepthPoint>& points, const ImagePyramid& ref, int w,
                              int h, int levels, int memory_fraction) {
  DepthMapPyramid maps(w, h, levels);
  DepthMapCanvas canvas(w, h, levels);
  maps.build(points.data(), points.size(), ref, canvas);

  // Dense planes, as DepthMapPyramid had them: splat, 2x2 sums, one dilation per level.
  const float ratio = 1.25f;
  std::vector<std::vector<float>> sum(levels), weight(levels);
  std::vector<unsigned char> from_map(static_cast<std::size_t>(w) * h, 0);
  for (int l = 0; l < levels; ++l) {
    sum[l].assign(static_cast<std::size_t>(w >> l) * (h >> l), 0.f);
    weight[l] = sum[l];
  }
  for (const DepthPoint& p : points) {
    const float fx = std::floor(p.u + 0.5f), fy = std::floor(p.v + 0.5f);
    if (!(fx >= 0.f && fy >= 0.f && fx < w && fy < h)) continue;
    const int i = static_cast<int>(fy) * w + static_cast<int>(fx);
    if (!(weight[0][i] > 0.f)) {
      from_map[i] = p.from_map;
    } else if (p.from_map != (from_map[i] != 0)) {
      const float seen = sum[0][i] / weight[0][i];
      if (p.idepth * ratio < seen) continue;
      if (p.idepth > ratio * seen) {
        sum[0][i] = p.weight * p.idepth;
        weight[0][i] = p.weight;
        from_map[i] = p.from_map;
        continue;
      }
    }
    sum[0][i] += p.weight * p.idepth;
    weight[0][i] += p.weight;
  }
  for (int l = 1; l < levels; ++l) {
    const int lw = w >> l, lh = h >> l, sw = w >> (l - 1);
    for (int y = 0; y < lh; ++y)
      for (int x = 0; x < lw; ++x) {
        const int c = 2 * y * sw + 2 * x;
        sum[l][y * lw + x] =
            sum[l - 1][c] + sum[l - 1][c + 1] + sum[l - 1][c + sw] + sum[l - 1][c + sw + 1];
        weight[l][y * lw + x] = weight[l - 1][c] + weight[l - 1][c + 1] + weight[l - 1][c + sw] +
                                weight[l - 1][c + sw + 1];
      }
  }
  for (int l = 0; l < levels; ++l) {
    const int lw = w >> l, lh = h >> l;
    static constexpr int kDiagonal[4][2] = {{-1, -1}, {1, -1}, {-1, 1}, {1, 1}};
    static constexpr int kCross[4][2] = {{0, -1}, {-1, 0}, {1, 0}, {0, 1}};
    const int(*offsets)[2] = l < 2 ? kDiagonal : kCross;
    std::vector<float> s2 = sum[l], w2 = weight[l];
    for (int y = 0; y < lh; ++y)
      for (int x = 0; x < lw; ++x) {
        if (weight[l][y * lw + x] > 0.f) continue;
        float s = 0.f, ws = 0.f, lo = std::numeric_limits<float>::infinity(), hi = 0.f;
        for (int k = 0; k < 4; ++k) {
          const int nx = x + offsets[k][0], ny = y + offsets[k][1];
          if (nx < 0 || ny < 0 || nx >= lw || ny >= lh || !(weight[l][ny * lw + nx] > 0.f))
            continue;
          const float sn = sum[l][ny * lw + nx], wn = weight[l][ny * lw + nx];
          s += sn;
          ws += wn;
          lo = std::min(lo, sn / wn);
          hi = std::max(hi, sn / wn);
        }
        if (ws > 0.f && hi <= ratio * lo) {
          s2[y * lw + x] = s;
          w2[y * lw + x] = ws;
        }
      }
    int n = 0;
    for (int y = 0; y < lh; ++y)
      for (int x = 0; x < lw; ++x) {
        const float expected = w2[y * lw + x] > 0.f ? s2[y * lw + x] / w2[y * lw + x] : 0.f;
        ASSERT_EQ(canvas.idepthAt(l, x, y), expected) << "level " << l << ": " << x << ", " << y;
        if (w2[y * lw + x] > 0.f) {
          ASSERT_LT(n, maps.points(l).count);
          ASSERT_EQ(maps.points(l).x[n], static_cast<float>(x));
          ASSERT_EQ(maps.points(l).y[n], static_cast<float>(y));
          ASSERT_EQ(maps.points(l).idepth[n], expected);
          ++n;
        }
      }
    EXPECT_EQ(n, maps.points(l).count) << "level " << l;
  }
  // The dense planes' sums and weights took 8 bytes per pixel on every level, and level 0's
  // surface origin one more: a window's 3000 points (kitti00_200 and vamr_desk_loop have at most
  // 3240 pixels at level 0) take less than half of that; four times as many, no more.
  const std::size_t dense = (2 * sizeof(float) * static_cast<std::size_t>(w) * h) * 4 / 3 +
                            static_cast<std::size_t>(w) * h;
  EXPECT_LT(canvas.bytes(), dense / static_cast<std::size_t>(memory_fraction));
}

TEST(DepthMapPyramidTest, RejectsACanvasOfAnotherSize) {
  const ImagePyramid ref = makeReference();
  DepthMapPyramid maps(kW, kH, kLevels);
  DepthMapCanvas wider(kW * 2, kH, kLevels);
  DepthMapCanvas fewer_levels(kW, kH, 2);
  EXPECT_THROW(maps.build(nullptr, 0, ref, wider), InputError);
  EXPECT_THROW(maps.build(nullptr, 0, ref, fewer_levels), InputError);
  EXPECT_THROW(DepthMapCanvas(0, 10, 1), InputError);
  EXPECT_THROW(DepthMapCanvas(64, 48, 8), ConfigError);
}

}  // namespace
}  // namespace ldsm
