#include "features/pixel_selector.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "ldsm/error.h"
#include "synthetic_images.h"

namespace ldsm {
namespace {

using test::makePyramid;
using test::renderImage;

constexpr int kW = 640;
constexpr int kH = 480;

ImageF texturedImage(std::uint32_t seed = 1) {
  return renderImage(kW, kH, [&](double x, double y) {
    return test::texture(x, y, 16.0, seed) + test::pixelNoise(int(x), int(y), 1.0);
  });
}

int countCorners(const std::vector<SelectedPixel>& pts) {
  int n = 0;
  for (const auto& p : pts) n += p.is_corner;
  return n;
}

TEST(PixelSelector, CountIsNearTargetOnTexture) {
  const ImagePyramid pyr = makePyramid(texturedImage(), 4);
  PointSelectionConfig config;
  PixelSelector selector(kW, kH, config);
  std::vector<SelectedPixel> pts;
  for (float density : {1.f, 0.5f, 2.f}) {
    const int n = selector.select(pyr, density, pts);
    const double target = config.points_per_keyframe * density;
    EXPECT_EQ(n, static_cast<int>(pts.size()));
    EXPECT_NEAR(n, target, 0.1 * target) << "density " << density;
    // Corners are listed first and make up about corner_fraction of the target.
    const int corners = countCorners(pts);
    EXPECT_GT(corners, 100);  // the texture has a few hundred good corners
    EXPECT_LE(corners, std::lround(config.corner_fraction * target));
    for (int i = 0; i < corners; ++i) EXPECT_TRUE(pts[i].is_corner);
  }
}

TEST(PixelSelector, PointsAreInsideTheBorderAndUnique) {
  const ImagePyramid pyr = makePyramid(texturedImage(3), 4);
  PixelSelector selector(kW, kH, PointSelectionConfig{});
  std::vector<SelectedPixel> pts;
  selector.select(pyr, 1.f, pts);
  ImageU8 seen(kW, kH, 0);
  for (const auto& p : pts) {
    const int border = p.is_corner ? PixelSelector::kCornerBorder : PixelSelector::kBorder;
    ASSERT_GE(p.u, border - 0.5f);
    ASSERT_GE(p.v, border - 0.5f);
    ASSERT_LE(p.u, kW - 1 - border + 0.5f);
    ASSERT_LE(p.v, kH - 1 - border + 0.5f);
    ASSERT_GE(p.level, 0);
    ASSERT_LE(p.level, 2);
    const int x = static_cast<int>(std::lround(p.u)), y = static_cast<int>(std::lround(p.v));
    EXPECT_EQ(seen(x, y), 0) << "pixel selected twice: " << x << ", " << y;
    seen(x, y) = 1;
  }
}

TEST(PixelSelector, SpreadsOverUniformTexture) {
  const ImagePyramid pyr = makePyramid(texturedImage(5), 4);
  PixelSelector selector(kW, kH, PointSelectionConfig{});
  std::vector<SelectedPixel> pts;
  const int n = selector.select(pyr, 1.f, pts);
  int counts[4][4] = {};
  for (const auto& p : pts) {
    counts[std::min(int(p.v * 4 / kH), 3)][std::min(int(p.u * 4 / kW), 3)]++;
  }
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) {
      // A fair share is n / 16; allow for the border and for texture variation.
      EXPECT_GT(counts[j][i], 0.4 * n / 16) << "region " << i << ", " << j;
    }
  }
}

TEST(PixelSelector, FlatImagesGiveAlmostNothing) {
  PixelSelector selector(kW, kH, PointSelectionConfig{});
  std::vector<SelectedPixel> pts;
  const ImagePyramid flat =
      makePyramid(renderImage(kW, kH, [](double, double) { return 128.0; }), 4);
  EXPECT_EQ(selector.select(flat, 1.f, pts), 0);
  // Sensor-like noise (sigma 2 grey levels) must not be mistaken for texture.
  const ImagePyramid noisy = makePyramid(
      renderImage(kW, kH,
                  [](double x, double y) { return 128.0 + test::pixelNoise(int(x), int(y), 2.0); }),
      4);
  EXPECT_LT(selector.select(noisy, 1.f, pts), 20);
}

TEST(PixelSelector, FlatHalfGetsNothingAndTexturedHalfGetsMore) {
  const ImageF img = renderImage(kW, kH, [](double x, double y) {
    return x < kW / 2 ? test::texture(x, y, 16.0) : 100.0 + test::pixelNoise(int(x), int(y), 1.0);
  });
  const ImagePyramid pyr = makePyramid(img, 4);
  PixelSelector selector(kW, kH, PointSelectionConfig{});
  std::vector<SelectedPixel> pts;
  const int n = selector.select(pyr, 1.f, pts);
  for (const auto& p : pts) EXPECT_LT(p.u, kW / 2 + 3) << "point on the flat half";
  // The grid adapts: the textured half gets (nearly) the whole budget.
  EXPECT_GT(n, 0.8 * PointSelectionConfig{}.points_per_keyframe);
}

TEST(PixelSelector, WeakSmoothStructureIsFoundOnCoarseLevels) {
  // Broad blobs: level-0 gradients (< 4 grey levels / pixel) stay below the threshold (>= 7), the
  // coarser levels see them.
  const ImageF img = renderImage(kW, kH, [](double x, double y) {
    return 60.0 + 120.0 * test::valueNoise(x / 48.0, y / 48.0, 9);
  });
  const ImagePyramid pyr = makePyramid(img, 4);
  PixelSelector selector(kW, kH, PointSelectionConfig{});
  std::vector<SelectedPixel> pts;
  const int n = selector.select(pyr, 1.f, pts);
  int coarse = 0;
  for (const auto& p : pts) {
    if (!p.is_corner) {
      EXPECT_GT(p.level, 0) << "level-0 pick at " << p.u << ", " << p.v;
      coarse += p.level > 0;
    }
  }
  EXPECT_GT(coarse, 50) << n;
}

TEST(PixelSelector, NoGradientPointNextToACorner) {
  const ImageF img = test::renderSupersampled(kW, kH, [](double x, double y) {
    return 0.5 * test::checkerboard(x, y, 40.0, 10.3, 7.6) + 0.5 * test::texture(x, y, 16.0);
  });
  const ImagePyramid pyr = makePyramid(img, 4);
  PixelSelector selector(kW, kH, PointSelectionConfig{});
  std::vector<SelectedPixel> pts;
  selector.select(pyr, 1.f, pts);
  const int corners = countCorners(pts);
  ASSERT_GT(corners, 50);
  for (const auto& c : pts) {
    if (!c.is_corner) continue;
    for (const auto& p : pts) {
      if (p.is_corner) continue;
      EXPECT_GT(std::hypot(p.u - c.u, p.v - c.v), 2.f)
          << "point " << p.u << ", " << p.v << " next to corner " << c.u << ", " << c.v;
    }
  }
}

// A saturated disc on texture: clipped pixels do not follow the brightness model (their border
// moves when the exposure changes), so no point's residual pattern may touch one.
TEST(PixelSelector, KeepsItsMarginFromClippedPixels) {
  const ImageF tex = texturedImage(5);
  ImageF img(kW, kH);
  ImageF raw(kW, kH);
  const auto in_disc = [](int x, int y) { return std::hypot(x - 320.0, y - 240.0) < 90.0; };
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      raw(x, y) = in_disc(x, y) ? 255.f : tex(x, y);
      img(x, y) = raw(x, y);
    }
  ImagePyramid pyr = makePyramid(img, 4);
  const auto nearest_clipped = [&](const SelectedPixel& p) {
    const int cx = static_cast<int>(p.u + 0.5f), cy = static_cast<int>(p.v + 0.5f);
    int best = 1 << 20;
    for (int y = std::max(cy - 20, 0); y < std::min(cy + 21, kH); ++y)
      for (int x = std::max(cx - 20, 0); x < std::min(cx + 21, kW); ++x)
        if (in_disc(x, y)) best = std::min(best, std::max(std::abs(x - cx), std::abs(y - cy)));
    return best;
  };
  PointSelectionConfig config;
  config.clipped_margin = 4;
  PixelSelector selector(kW, kH, config);
  std::vector<SelectedPixel> pts;

  // Without the mask the disc's rim is the strongest edge in the image and gets points.
  selector.select(pyr, 1.f, pts);
  int on_rim = 0;
  for (const auto& p : pts) on_rim += nearest_clipped(p) <= config.clipped_margin;
  EXPECT_GT(on_rim, 20);

  pyr.markClipped(raw.view(), 250.f);
  const int n = selector.select(pyr, 1.f, pts);
  EXPECT_GT(n, 0.7 * config.points_per_keyframe);
  for (const auto& p : pts)
    EXPECT_GT(nearest_clipped(p), config.clipped_margin)
        << (p.is_corner ? "corner " : "point ") << p.u << ", " << p.v;
}

TEST(PixelSelector, IsDeterministic) {
  const ImagePyramid a = makePyramid(texturedImage(11), 4);
  const ImagePyramid b = makePyramid(texturedImage(12), 4);
  PixelSelector s1(kW, kH, PointSelectionConfig{});
  PixelSelector s2(kW, kH, PointSelectionConfig{});
  std::vector<SelectedPixel> p1, p2, p3;
  s1.select(a, 1.f, p1);
  s2.select(b, 1.f, p3);  // different history
  s2.select(a, 1.f, p2);
  ASSERT_EQ(p1.size(), p2.size());
  for (std::size_t i = 0; i < p1.size(); ++i) {
    EXPECT_EQ(p1[i].u, p2[i].u);
    EXPECT_EQ(p1[i].v, p2[i].v);
    EXPECT_EQ(p1[i].level, p2[i].level);
    EXPECT_EQ(p1[i].is_corner, p2[i].is_corner);
    EXPECT_EQ(p1[i].score, p2[i].score);
  }
}

TEST(PixelSelector, MoreCornersFromTheSameScoresAreThoseDetectCornersGives) {
  const ImagePyramid a = makePyramid(texturedImage(21), 4);
  for (const double corner_fraction : {0.1, 0.0}) {
    PointSelectionConfig config;
    config.corner_fraction = corner_fraction;
    PixelSelector s1(kW, kH, config), s2(kW, kH, config);
    std::vector<SelectedPixel> p1, p2;
    std::vector<Corner> c1, c2;
    s1.select(a, 1.f, p1, PixelSelector::CornerLimits{300, 9.f}, &c1);
    s2.select(a, 1.f, p2);
    s2.detectCorners(a, 300, 9.f, c2);
    ASSERT_EQ(p1.size(), p2.size()) << corner_fraction;
    for (std::size_t i = 0; i < p1.size(); ++i) {
      EXPECT_EQ(p1[i].u, p2[i].u);
      EXPECT_EQ(p1[i].v, p2[i].v);
      EXPECT_EQ(p1[i].is_corner, p2[i].is_corner);
    }
    EXPECT_GT(c1.size(), 100u);
    ASSERT_EQ(c1.size(), c2.size()) << corner_fraction;
    for (std::size_t i = 0; i < c1.size(); ++i) {
      EXPECT_EQ(c1[i].u, c2[i].u);
      EXPECT_EQ(c1[i].v, c2[i].v);
      EXPECT_EQ(c1[i].score, c2[i].score);
    }
  }
}

TEST(PixelSelector, FavoursDiverseGradientDirections) {
  // Bands of 12 rows alternate between diagonal stripes (|grad I| up to 42) and vertical stripes
  // (|grad I| up to 34, gradient along x). Every cell holds both; picking by magnitude alone
  // would take only diagonal gradients.
  const ImageF img = renderImage(kW, kH, [](double x, double y) {
    const double w = 0.5 + 0.5 * std::tanh(3.0 * std::sin(2 * M_PI * y / 24.0));
    return 128.0 + w * 60.0 * std::sin(0.5 * (x + y)) + (1 - w) * 56.0 * std::sin(0.6 * x);
  });
  PointSelectionConfig config;
  config.corner_fraction = 0.0;
  config.min_gradient = 2.0;
  PixelSelector selector(kW, kH, config);
  std::vector<SelectedPixel> pts;
  const ImagePyramid pyr = makePyramid(img, 4);
  selector.select(pyr, 1.f, pts);
  ASSERT_GT(pts.size(), 1000u);
  int along_x = 0;
  const auto g = pyr.gradients(0);
  for (const auto& p : pts) {
    const auto& px = g(int(p.u), int(p.v));
    along_x += std::abs(px.dy) < 0.3f * std::abs(px.dx);
  }
  EXPECT_GT(along_x, 0.15 * pts.size());
}

TEST(PixelSelector, RejectsBadInput) {
  PointSelectionConfig config;
  PixelSelector selector(kW, kH, config);
  std::vector<SelectedPixel> pts;
  const ImagePyramid small =
      makePyramid(renderImage(320, 240, [](double, double) { return 1.0; }), 2);
  EXPECT_THROW(selector.select(small, 1.f, pts), InputError);
  const ImagePyramid pyr = makePyramid(texturedImage(), 3);
  EXPECT_THROW(selector.select(pyr, 0.f, pts), InputError);
  EXPECT_THROW(selector.select(pyr, -1.f, pts), InputError);
  EXPECT_THROW(selector.select(pyr, std::numeric_limits<float>::quiet_NaN(), pts), InputError);
  EXPECT_THROW(selector.select(pyr, std::numeric_limits<float>::infinity(), pts), InputError);

  PointSelectionConfig bad = config;
  bad.corner_fraction = 1.5;
  EXPECT_THROW(PixelSelector(kW, kH, bad), ConfigError);
  bad = config;
  bad.grid_block_size = 0;
  EXPECT_THROW(PixelSelector(kW, kH, bad), ConfigError);
  bad = config;
  bad.points_per_keyframe = 0;
  EXPECT_THROW(PixelSelector(kW, kH, bad), ConfigError);
  bad = config;
  bad.min_gradient = -1;
  EXPECT_THROW(PixelSelector(kW, kH, bad), ConfigError);
  EXPECT_THROW(PixelSelector(0, kH, config), InputError);
}

TEST(PixelSelector, ImagesSmallerThanTheBorderGiveNothing) {
  PixelSelector selector(6, 5, PointSelectionConfig{});
  std::vector<SelectedPixel> pts;
  const ImagePyramid pyr = makePyramid(
      renderImage(6, 5, [](double x, double y) { return 100.0 * ((int(x) + int(y)) % 2); }), 1);
  EXPECT_EQ(selector.select(pyr, 1.f, pts), 0);
}

TEST(PixelSelector, WorksWithASingleLevelAndTinyImages) {
  const ImageF img =
      renderImage(40, 30, [](double x, double y) { return test::texture(x, y, 6.0); });
  PixelSelector selector(40, 30, PointSelectionConfig{});
  std::vector<SelectedPixel> pts;
  const ImagePyramid pyr = makePyramid(img, 1);
  const int n = selector.select(pyr, 1.f, pts);
  EXPECT_GT(n, 0);
  EXPECT_EQ(countCorners(pts), 0);  // no room for the ORB border
  for (const auto& p : pts) EXPECT_EQ(p.level, 0);
}

}  // namespace
}  // namespace ldsm
