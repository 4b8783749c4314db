#include "features/corner_detector.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "ldsm/error.h"
#include "synthetic_images.h"

namespace ldsm {
namespace {

using test::makePyramid;
using test::renderSupersampled;

constexpr int kW = 320;
constexpr int kH = 240;

std::vector<Corner> detect(const ImageF& img, int max_corners = 300) {
  const ImagePyramid pyr = makePyramid(img, 1);
  CornerDetector detector(img.width(), img.height());
  CornerParams params;
  params.max_corners = max_corners;
  std::vector<Corner> corners;
  detector.detect(pyr.gradients(0), params, corners);
  return corners;
}

/// Distance from (u, v) to the nearest of `points`.
double nearest(const std::vector<Eigen::Vector2d>& points, double u, double v) {
  double best = 1e9;
  for (const auto& p : points) best = std::min(best, std::hypot(p.x() - u, p.y() - v));
  return best;
}

TEST(CornerDetector, FindsCheckerboardJunctions) {
  const double square = 24.0, ox = 5.3, oy = 9.7;
  const ImageF img = renderSupersampled(
      kW, kH, [&](double x, double y) { return test::checkerboard(x, y, square, ox, oy); });
  const std::vector<Corner> corners = detect(img);
  // Pixel centres are at integer coordinates of the rendering functions' frame, so junctions are
  // at (ox + i square, oy + j square) in pixels.
  std::vector<Eigen::Vector2d> truth;
  for (double y = oy; y < kH; y += square) {
    for (double x = ox; x < kW; x += square) {
      const double u = x, v = y;
      if (u >= 18 && v >= 18 && u <= kW - 1 - 18 && v <= kH - 1 - 18) truth.emplace_back(u, v);
    }
  }
  ASSERT_GT(truth.size(), 50u);
  for (const Corner& c : corners) {
    EXPECT_GE(c.u, 16 - 0.5f);
    EXPECT_LE(c.u, kW - 1 - 16 + 0.5f);
    EXPECT_LT(nearest(truth, c.u, c.v), 1.0) << "corner off a junction: " << c.u << ", " << c.v;
  }
  std::vector<Eigen::Vector2d> found;
  for (const Corner& c : corners) found.emplace_back(c.u, c.v);
  int detected = 0;
  for (const auto& t : truth) detected += nearest(found, t.x(), t.y()) < 1.0;
  EXPECT_GE(detected, 0.95 * truth.size());
}

TEST(CornerDetector, FindsTheCornersOfSquares) {
  // Bright squares on a dark background: L-shaped corners.
  struct Square {
    double x0, y0, size;
  };
  const std::vector<Square> squares = {
      {40.2, 30.6, 30}, {120.7, 50.1, 40}, {200.4, 120.3, 50}, {60.5, 150.8, 35}};
  const ImageF img = renderSupersampled(kW, kH, [&](double x, double y) {
    for (const auto& s : squares) {
      if (x >= s.x0 && x < s.x0 + s.size && y >= s.y0 && y < s.y0 + s.size) return 190.0;
    }
    return 40.0;
  });
  const std::vector<Corner> corners = detect(img);
  std::vector<Eigen::Vector2d> truth;
  for (const auto& s : squares) {
    for (double dy : {0.0, s.size})
      for (double dx : {0.0, s.size}) truth.emplace_back(s.x0 + dx, s.y0 + dy);
  }
  EXPECT_EQ(corners.size(), truth.size());
  std::vector<Eigen::Vector2d> found;
  // The min-eigenvalue peak of an L-corner lies about 1.5 px inside the corner, along its
  // bisector (the 5x5 window must hold both edges).
  for (const Corner& c : corners) {
    found.emplace_back(c.u, c.v);
    EXPECT_LT(nearest(truth, c.u, c.v), 2.5) << c.u << ", " << c.v;
  }
  for (const auto& t : truth) EXPECT_LT(nearest(found, t.x(), t.y()), 2.5) << t.transpose();
}

/// Fraction of the corners of image 1 re-detected within 1 px in image 2 = image 1 shifted.
double repeatability(const std::function<double(double, double)>& f, double sx, double sy) {
  const ImageF a = renderSupersampled(kW, kH, f);
  const ImageF b =
      renderSupersampled(kW, kH, [&](double x, double y) { return f(x - sx, y - sy); });
  const std::vector<Corner> ca = detect(a, 150);
  const std::vector<Corner> cb = detect(b, 150);
  std::vector<Eigen::Vector2d> found;
  for (const Corner& c : cb) found.emplace_back(c.u, c.v);
  int total = 0, repeated = 0;
  for (const Corner& c : ca) {
    const double u = c.u + sx, v = c.v + sy;
    if (u < 20 || v < 20 || u > kW - 21 || v > kH - 21) continue;  // may leave the valid area
    ++total;
    repeated += nearest(found, u, v) <= 1.0;
  }
  EXPECT_GT(total, 20);
  return total > 0 ? double(repeated) / total : 0.0;
}

TEST(CornerDetector, IsRepeatableUnderShift) {
  auto textured = [](double x, double y) { return test::texture(x, y, 12.0, 4); };
  EXPECT_GE(repeatability(textured, 2.4, 1.7), 0.8);
  EXPECT_GE(repeatability(textured, -3.3, 0.5), 0.8);
  auto board = [](double x, double y) {
    return 0.6 * test::checkerboard(x, y, 30.0, 3.0, 2.0) + 0.4 * test::texture(x, y, 12.0, 8);
  };
  EXPECT_GE(repeatability(board, 1.6, -2.2), 0.8);
}

TEST(CornerDetector, RespectsMinimumDistanceAndCount) {
  const ImageF img =
      renderSupersampled(kW, kH, [](double x, double y) { return test::texture(x, y, 12.0); });
  const ImagePyramid pyr = makePyramid(img, 1);
  CornerDetector detector(kW, kH);
  CornerParams params;
  params.max_corners = 60;
  params.min_distance = 12.f;
  std::vector<Corner> corners;
  EXPECT_EQ(detector.detect(pyr.gradients(0), params, corners), 60);
  for (std::size_t i = 0; i < corners.size(); ++i) {
    if (i > 0) {
      EXPECT_LE(corners[i].score, corners[i - 1].score);  // strongest first
    }
    for (std::size_t j = 0; j < i; ++j) {
      // Integer positions are >= 12 apart; sub-pixel refinement moves each by <= 0.5 per axis.
      EXPECT_GT(std::hypot(corners[i].u - corners[j].u, corners[i].v - corners[j].v), 12.f - 1.5f);
    }
  }
  // The scores are the Shi-Tomasi min eigenvalue: check one against a direct computation.
  const Corner& c = corners.front();
  const int x = static_cast<int>(std::lround(c.u)), y = static_cast<int>(std::lround(c.v));
  double a = 0, b = 0, d = 0;
  for (int j = -2; j <= 2; ++j) {
    for (int i = -2; i <= 2; ++i) {
      const GradientPixel& g = pyr.gradients(0)(x + i, y + j);
      a += g.dx * g.dx;
      b += g.dx * g.dy;
      d += g.dy * g.dy;
    }
  }
  a /= 25, b /= 25, d /= 25;
  const double min_eig = 0.5 * (a + d) - std::sqrt(0.25 * (a - d) * (a - d) + b * b);
  EXPECT_NEAR(detector.scores()(x, y), min_eig, 1e-3 * min_eig);
}

TEST(CornerDetector, IgnoresFlatAndNoisyImages) {
  const ImageF img = test::renderImage(
      kW, kH, [](double x, double y) { return 90.0 + test::pixelNoise(int(x), int(y), 2.0); });
  EXPECT_TRUE(detect(img).empty());
}

void expectSameCorners(const std::vector<Corner>& a, const std::vector<Corner>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].u, b[i].u) << i;
    EXPECT_EQ(a[i].v, b[i].v) << i;
    EXPECT_EQ(a[i].score, b[i].score) << i;
  }
}

TEST(CornerDetector, ReselectingFromTheScoresEqualsDetectingAgain) {
  const ImageF img =
      renderSupersampled(kW, kH, [](double x, double y) { return test::texture(x, y, 12.0); });
  const ImagePyramid pyr = makePyramid(img, 1);
  CornerParams first;
  first.max_corners = 40;
  first.min_score = 60.f;
  first.border = 16;
  CornerParams second = first;
  second.max_corners = 200;
  second.min_score = 9.f;
  second.min_distance = 6.f;
  CornerDetector detector(kW, kH), fresh(kW, kH);
  std::vector<Corner> a, b, c;
  ASSERT_EQ(detector.detect(pyr.gradients(0), first, a), 40);
  const int n = detector.reselect(second, b);
  EXPECT_GT(n, 40);
  fresh.detect(pyr.gradients(0), second, c);
  expectSameCorners(b, c);
  // And back: the scores are unchanged by a reselection.
  detector.reselect(first, c);
  expectSameCorners(a, c);
}

TEST(CornerDetector, ReselectingNeedsScoresWithTheSameBorder) {
  const ImageF img =
      renderSupersampled(kW, kH, [](double x, double y) { return test::texture(x, y, 12.0); });
  const ImagePyramid pyr = makePyramid(img, 1);
  CornerDetector detector(kW, kH);
  std::vector<Corner> corners;
  EXPECT_THROW(detector.reselect(CornerParams{}, corners), InputError);  // nothing computed yet
  CornerParams params;
  detector.detect(pyr.gradients(0), params, corners);
  params.border = 20;
  EXPECT_THROW(detector.reselect(params, corners), InputError);
  params.max_corners = 0;  // a detect() that computed no scores
  detector.detect(pyr.gradients(0), params, corners);
  params.max_corners = 10;
  EXPECT_THROW(detector.reselect(params, corners), InputError);
}

TEST(CornerDetector, RejectsWrongImageSize) {
  CornerDetector detector(kW, kH);
  const ImagePyramid pyr = makePyramid(ImageF(100, 80, 0.f), 1);
  std::vector<Corner> corners;
  EXPECT_THROW(detector.detect(pyr.gradients(0), CornerParams{}, corners), InputError);
  EXPECT_THROW(CornerDetector(0, 10), InputError);
}

}  // namespace
}  // namespace ldsm
