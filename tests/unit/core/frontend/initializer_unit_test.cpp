// Building blocks and contracts of the coarse initializer: point selection and links, gradients
// against numeric differentiation, the parallax measure, bad input, failures and restarts.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "frontend/init_point_graph.h"
#include "init_access.h"
#include "init_test_util.h"
#include "ldsm/error.h"

namespace ldsm {
namespace {

using init_test::makeIntrinsics;
using Access = CoarseInitializerAccess;

constexpr double kDeg = 3.14159265358979323846 / 180.0;

ImagePyramid renderPyramid(const init_test::InitScene& scene, const SE3d& pose,
                           const PinholeIntrinsics& K, float noise = 0.f, unsigned seed = 1) {
  std::mt19937 rng(seed);
  ImagePyramid pyramid(K.width, K.height, 5);
  const ImageF image = scene.render(pose, K, 1, noise, &rng);
  pyramid.build(image.view());
  return pyramid;
}

ImagePyramid flatPyramid(int width, int height, float value) {
  ImageF image(width, height, value);
  ImagePyramid pyramid(width, height, 5);
  pyramid.build(image.view());
  return pyramid;
}

// ---- point selection and links ---------------------------------------------------------------

TEST(InitPointGraph, BestGradientPerCellPicksTheCellMaximumAboveThreshold) {
  const PinholeIntrinsics K = makeIntrinsics(160, 120, 120);
  const ImagePyramid pyr = renderPyramid(init_test::wallAndFloorScene(), SE3d(), K);
  const ImageView<const GradientPixel> g = pyr.gradients(0);
  const int cell = 5, margin = 3;
  const float min_grad = 4.f;
  std::vector<Eigen::Vector2f> picks;
  const int n = selectBestGradientPerCell(g, cell, min_grad, margin, picks);
  ASSERT_EQ(n, static_cast<int>(picks.size()));
  ASSERT_GT(n, 100);
  const auto mag = [&](int x, int y) { return g(x, y).dx * g(x, y).dx + g(x, y).dy * g(x, y).dy; };
  std::vector<int> per_cell(10000, 0);
  for (const Eigen::Vector2f& p : picks) {
    const int x = static_cast<int>(p.x()), y = static_cast<int>(p.y());
    ASSERT_GE(x, margin);
    ASSERT_GE(y, margin);
    ASSERT_LT(x, K.width - margin);
    ASSERT_LT(y, K.height - margin);
    EXPECT_GE(mag(x, y), min_grad * min_grad);
    const int cx = (x - margin) / cell, cy = (y - margin) / cell;
    ++per_cell[static_cast<std::size_t>(cy * 100 + cx)];
    // No pixel of the same cell has a larger gradient.
    for (int yy = margin + cy * cell; yy < std::min(margin + (cy + 1) * cell, K.height - margin);
         ++yy) {
      for (int xx = margin + cx * cell; xx < std::min(margin + (cx + 1) * cell, K.width - margin);
           ++xx) {
        EXPECT_LE(mag(xx, yy), mag(x, y));
      }
    }
  }
  for (const int c : per_cell) EXPECT_LE(c, 1);

  const ImagePyramid flat = flatPyramid(160, 120, 90.f);
  EXPECT_EQ(selectBestGradientPerCell(flat.gradients(0), cell, min_grad, margin, picks), 0);
}

TEST(InitPointGraph, BucketGridNearestMatchesBruteForce) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> ux(0.f, 200.f), uy(0.f, 90.f);
  std::vector<Eigen::Vector2f> points;
  for (int i = 0; i < 700; ++i) points.emplace_back(ux(rng), uy(rng));
  PointBucketGrid grid;
  grid.build(points, 7.f, 200, 90);
  std::vector<int> found;
  for (const int k : {1, 4, 10}) {
    for (int q = 0; q < 200; ++q) {
      const bool self = q % 2 == 0;
      const Eigen::Vector2f query = self ? points[static_cast<std::size_t>(q)]
                                         : Eigen::Vector2f(ux(rng) * 1.1f - 10.f, uy(rng));
      const int skip = self ? q : -1;
      grid.nearest(query, k, skip, found);
      std::vector<std::pair<float, int>> all;
      for (int i = 0; i < static_cast<int>(points.size()); ++i) {
        if (i != skip)
          all.emplace_back((points[static_cast<std::size_t>(i)] - query).squaredNorm(), i);
      }
      std::sort(all.begin(), all.end());
      ASSERT_EQ(static_cast<int>(found.size()), k);
      for (int j = 0; j < k; ++j) {
        EXPECT_FLOAT_EQ(
            (points[static_cast<std::size_t>(found[static_cast<std::size_t>(j)])] - query)
                .squaredNorm(),
            all[static_cast<std::size_t>(j)].first);
      }
    }
  }
}

TEST(CoarseInitializer, ReferenceLinksNeighboursAndParents) {
  const PinholeIntrinsics K = makeIntrinsics(320, 240, 250);
  CoarseInitializer init(PyramidCamera(K, 5));
  const ImagePyramid pyr = renderPyramid(init_test::wallAndFloorScene(), SE3d(), K);
  EXPECT_FALSE(init.addFrame(pyr, 1.0));
  ASSERT_EQ(init.status(), InitStatus::kWaitingForParallax);
  ASSERT_GE(init.levels(), 3);
  for (int l = 0; l < init.levels(); ++l) {
    const auto& u = Access::pixels(init, l);
    ASSERT_GT(u.size(), 10u);
    for (int i = 0; i < static_cast<int>(u.size()); i += 7) {
      int count = 0;
      const auto& nb = Access::neighbours(init, l, i, &count);
      EXPECT_EQ(count, init.settings().neighbours);
      float last = 0.f;
      for (int j = 0; j < count; ++j) {
        EXPECT_NE(nb[static_cast<std::size_t>(j)], i);
        const float dist = (u[static_cast<std::size_t>(nb[static_cast<std::size_t>(j)])] -
                            u[static_cast<std::size_t>(i)])
                               .norm();
        EXPECT_GE(dist, last);  // nearest first
        last = dist;
      }
      if (l + 1 < init.levels()) {
        const int p = Access::parents(init, l)[static_cast<std::size_t>(i)];
        if (p >= 0) {
          const Eigen::Vector2f up = (u[static_cast<std::size_t>(i)].array() + 0.5f) * 0.5f - 0.5f;
          EXPECT_LT((Access::pixels(init, l + 1)[static_cast<std::size_t>(p)] - up).norm(), 12.f);
        }
      }
    }
  }
}

// ---- gradients against numeric differentiation -----------------------------------------------

TEST(CoarseInitializer, EnergyGradientMatchesNumericDifferentiation) {
  // The frame is a smooth analytic image (wavelengths >= 100 pixels), so that the interpolated
  // central-difference gradients of the Jacobians equal the derivative of the bilinear
  // interpolation the energy uses; without the gradient-dependent weight (not differentiated by
  // design), the only approximation left is the pattern sharing its centre's geometric Jacobian.
  const PinholeIntrinsics K = makeIntrinsics(320, 240, 250);
  CoarseInitializerSettings s;
  s.affine_prior_weight_a = 0.f;
  s.affine_prior_weight_b = 0.f;
  s.gradient_weight_c = 0.f;
  s.outlier_rms = 1e4f;  // no outlier cap: the energy must be smooth for differencing
  CoarseInitializer init(PyramidCamera(K, 5), s);
  init.addFrame(renderPyramid(init_test::wallAndFloorScene(), SE3d(), K), 1.0);
  ImageF smooth(K.width, K.height);
  for (int y = 0; y < K.height; ++y) {
    for (int x = 0; x < K.width; ++x) {
      smooth(x, y) =
          static_cast<float>(120.0 + 60.0 * std::sin(0.025 * x + 0.3) * std::cos(0.02 * y) +
                             40.0 * std::sin(0.015 * x + 0.0225 * y + 1.0));
    }
  }
  ImagePyramid frame(K.width, K.height, 5);
  frame.build(smooth.view());

  for (const int level : {0, 1}) {
    std::vector<float> d(Access::pixels(init, level).size());
    for (std::size_t i = 0; i < d.size(); ++i) d[i] = 0.6f + 0.1f * static_cast<float>(i % 7);
    const SE3d T(SO3d::exp(Eigen::Vector3d(0.01, -0.02, 0.005)),
                 Eigen::Vector3d(0.03, -0.01, 0.02));
    const AffineLight affine{0.02, 1.5};
    Eigen::Matrix<double, 8, 1> b;
    std::vector<float> bd;
    std::vector<std::uint8_t> inliers;
    const std::vector<std::uint8_t> all(d.size(), 1);
    Access::energy(init, frame, level, T, affine, d, all, &b, &bd, &inliers);

    // Central differences over the points that stay inliers (an inlier turning into an outlier
    // or leaving the image makes the energy jump).
    std::vector<std::uint8_t> mask = inliers;
    std::vector<std::uint8_t> now;
    const auto energyAt = [&](const SE3d& Tx, const AffineLight& ax, const std::vector<float>& dx) {
      return Access::energy(init, frame, level, Tx, ax, dx, mask, nullptr, nullptr, nullptr);
    };
    const auto perturbed = [&](int j, double h, SE3d* Tx, AffineLight* ax) {
      *Tx = T;
      *ax = affine;
      if (j < 6) {
        Eigen::Matrix<double, 6, 1> delta = Eigen::Matrix<double, 6, 1>::Zero();
        delta(j) = h;
        *Tx = SE3d::exp(delta) * T;
      } else if (j == 6) {
        ax->a += h;
      } else {
        ax->b += h;
      }
    };
    const std::array<double, 8> step{{1e-4, 1e-4, 1e-4, 1e-4, 1e-4, 1e-4, 1e-4, 1e-2}};
    for (int j = 0; j < 8; ++j) {
      for (const double sign : {1.0, -1.0}) {
        SE3d Tx;
        AffineLight ax;
        perturbed(j, sign * step[static_cast<std::size_t>(j)], &Tx, &ax);
        Access::energy(init, frame, level, Tx, ax, d, all, nullptr, nullptr, &now);
        for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = mask[i] && now[i];
      }
    }
    int kept = 0;
    for (const auto m : mask) kept += m;
    ASSERT_GT(kept, static_cast<int>(
                        0.9 * static_cast<double>(std::count(inliers.begin(), inliers.end(), 1))));
    Eigen::Matrix<double, 8, 1> numeric;
    for (int j = 0; j < 8; ++j) {
      SE3d Tp, Tm;
      AffineLight ap, am;
      perturbed(j, step[static_cast<std::size_t>(j)], &Tp, &ap);
      perturbed(j, -step[static_cast<std::size_t>(j)], &Tm, &am);
      numeric(j) =
          (energyAt(Tp, ap, d) - energyAt(Tm, am, d)) / (2 * step[static_cast<std::size_t>(j)]);
    }
    Access::energy(init, frame, level, T, affine, d, mask, &b, nullptr, nullptr);
    for (int j = 0; j < 8; ++j) {
      EXPECT_NEAR(b(j), numeric(j), 0.03 * std::abs(numeric(j)) + 0.01 * numeric.norm())
          << "level " << level << " parameter " << j;
    }

    // Depth gradients of a sample of points (photometric part: bd minus the depth prior).
    int checked = 0;
    double err = 0, ref = 0;
    const float wp = init.settings().idepth_prior_weight;
    for (std::size_t i = 0; i < d.size(); i += 13) {
      if (!mask[i]) continue;
      std::vector<float> dp = d, dm = d;
      const float h = 1e-3f;
      dp[i] += h;
      dm[i] -= h;
      std::vector<std::uint8_t> one(d.size(), 0);
      one[i] = 1;
      const double num =
          (Access::energy(init, frame, level, T, affine, dp, one, nullptr, nullptr, nullptr) -
           Access::energy(init, frame, level, T, affine, dm, one, nullptr, nullptr, nullptr)) /
          (2 * h);
      const double analytic = bd[i] - wp * (d[i] - 1.f);
      err += (num - analytic) * (num - analytic);
      ref += num * num;
      ++checked;
    }
    ASSERT_GT(checked, 10);
    EXPECT_LT(std::sqrt(err / ref), 0.03) << "level " << level;
  }
}

// ---- parallax measure and degenerate maps ------------------------------------------------------

TEST(CoarseInitializer, RotationFreeParallaxSeparatesTranslationFromRotation) {
  const PinholeIntrinsics K = makeIntrinsics(320, 240, 250);
  CoarseInitializer init(PyramidCamera(K, 5));
  init.addFrame(renderPyramid(init_test::wallAndFloorScene(), SE3d(), K), 1.0);
  std::vector<float>& d = Access::idepth(init, 0);
  std::vector<std::uint8_t>& good = Access::good(init, 0);
  std::fill(good.begin(), good.end(), 1);
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> depth(0.5f, 1.5f);

  // Pure rotation: no parallax.
  for (float& v : d) v = depth(rng);
  Access::pose(init) =
      SE3d(SO3d::exp(Eigen::Vector3d(0.01, -0.02, 0.005)), Eigen::Vector3d::Zero());
  EXPECT_NEAR(Access::parallax(init), 0.0, 1e-6);

  // Sideways translation with equal depths: the flow (10 px) is nearly a rotation's, only the
  // perspective differs.
  std::fill(d.begin(), d.end(), 1.f);
  Access::pose(init) = SE3d(SO3d(), Eigen::Vector3d(0.04, 0, 0));
  const double uniform = Access::parallax(init);
  EXPECT_LT(uniform, 2.0);

  // The same translation over depths spread uniformly by +-50 %: parallax of about the flow's
  // standard deviation, 10 px * 0.5 / sqrt(3).
  for (float& v : d) v = depth(rng);
  const double varied = Access::parallax(init);
  EXPECT_GT(varied, 2.0);
  EXPECT_LT(varied, 3.5);
  EXPECT_GT(varied, 1.5 * uniform);

  // Forward motion: radial flow that no rotation explains.
  std::fill(d.begin(), d.end(), 1.f);
  Access::pose(init) = SE3d(SO3d(), Eigen::Vector3d(0, 0, -0.05));
  EXPECT_GT(Access::parallax(init), 3.0);
}

TEST(CoarseInitializer, DegenerateDepthDistributionsAreDetected) {
  const PinholeIntrinsics K = makeIntrinsics(320, 240, 250);
  CoarseInitializer init(PyramidCamera(K, 5));
  init.addFrame(renderPyramid(init_test::wallAndFloorScene(), SE3d(), K), 1.0);
  std::vector<float>& d = Access::idepth(init, 0);
  std::vector<std::uint8_t>& good = Access::good(init, 0);
  std::fill(good.begin(), good.end(), 1);
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> plausible(0.5f, 2.0f);
  for (float& v : d) v = plausible(rng);
  EXPECT_FALSE(Access::depthsDegenerate(init));

  // A quarter of the depths negative.
  for (std::size_t i = 0; i < d.size(); i += 4) d[i] = -0.3f;
  EXPECT_TRUE(Access::depthsDegenerate(init));

  // Hugely spread: 10 % of the points 50 times closer than the median.
  for (float& v : d) v = plausible(rng);
  for (std::size_t i = 0; i < d.size(); i += 10) d[i] = 60.f;
  EXPECT_TRUE(Access::depthsDegenerate(init));

  // No inliers at all.
  for (float& v : d) v = plausible(rng);
  std::fill(good.begin(), good.end(), 0);
  EXPECT_TRUE(Access::depthsDegenerate(init));
}

// ---- bad input, failures, restarts -----------------------------------------------------------

TEST(CoarseInitializer, InvalidSettingsAreRejected) {
  const PyramidCamera cam(makeIntrinsics(320, 240, 250), 5);
  const auto expectConfigError = [&](auto mutate) {
    CoarseInitializerSettings s;
    mutate(s);
    EXPECT_THROW(CoarseInitializer(cam, s), ConfigError);
  };
  expectConfigError([](CoarseInitializerSettings& s) { s.max_levels = 0; });
  expectConfigError([](CoarseInitializerSettings& s) { s.neighbours = 0; });
  expectConfigError([](CoarseInitializerSettings& s) { s.neighbours = 11; });
  expectConfigError([](CoarseInitializerSettings& s) { s.cell_size[1] = 0; });
  expectConfigError([](CoarseInitializerSettings& s) { s.huber_threshold = -1.f; });
  expectConfigError([](CoarseInitializerSettings& s) {
    s.huber_threshold = std::numeric_limits<float>::quiet_NaN();
  });
  expectConfigError([](CoarseInitializerSettings& s) { s.idepth_prior_weight = 0.f; });
  expectConfigError([](CoarseInitializerSettings& s) { s.min_parallax_flow = 0.f; });
  expectConfigError([](CoarseInitializerSettings& s) { s.min_rotation_free_parallax = 100.f; });
  expectConfigError([](CoarseInitializerSettings& s) { s.fail_rms = 1.f; });
  expectConfigError([](CoarseInitializerSettings& s) { s.min_good_fraction = 0.9f; });
  expectConfigError([](CoarseInitializerSettings& s) { s.max_idepth_spread = 0.5f; });
  expectConfigError([](CoarseInitializerSettings& s) { s.selector_density = 0.f; });
  EXPECT_THROW(CoarseInitializer(PyramidCamera(), CoarseInitializerSettings{}), InputError);
}

TEST(CoarseInitializer, BadFramesThrowInputError) {
  const PinholeIntrinsics K = makeIntrinsics(320, 240, 250);
  CoarseInitializer init(PyramidCamera(K, 5));
  const ImagePyramid good = renderPyramid(init_test::wallAndFloorScene(), SE3d(), K);
  const ImagePyramid wrong_size = flatPyramid(160, 120, 100.f);
  EXPECT_THROW(init.addFrame(wrong_size, 1.0), InputError);
  EXPECT_THROW(init.addFrame(good, 0.0), InputError);
  EXPECT_THROW(init.addFrame(good, -1.0), InputError);
  EXPECT_THROW(init.addFrame(good, std::numeric_limits<double>::quiet_NaN()), InputError);
  EXPECT_THROW(init.addFrame(good, std::numeric_limits<double>::infinity()), InputError);
  EXPECT_EQ(init.status(), InitStatus::kNoReference);  // nothing was accepted

  init.addFrame(good, 1.0);
  ASSERT_EQ(init.status(), InitStatus::kWaitingForParallax);
  ImagePyramid two_levels(K.width, K.height, 2);
  ImageF image(K.width, K.height, 80.f);
  two_levels.build(image.view());
  try {
    init.addFrame(two_levels, 1.0);
    FAIL() << "a pyramid with fewer levels than the reference must be rejected";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("levels"), std::string::npos) << e.what();
  }
  EXPECT_EQ(init.status(), InitStatus::kWaitingForParallax);  // the reference is kept
}

TEST(CoarseInitializer, NonFiniteImageIsReportedNotTracked) {
  const PinholeIntrinsics K = makeIntrinsics(320, 240, 250);
  CoarseInitializer init(PyramidCamera(K, 5));
  init.addFrame(renderPyramid(init_test::wallAndFloorScene(), SE3d(), K), 1.0);
  std::mt19937 rng(1);
  ImageF image = init_test::wallAndFloorScene().render(SE3d(SO3d(), {0.01, 0, 0}), K, 1, 0.f, &rng);
  for (int y = 100; y < 140; ++y) {
    for (int x = 140; x < 180; ++x) image(x, y) = std::numeric_limits<float>::quiet_NaN();
  }
  ImagePyramid pyramid(K.width, K.height, 5);
  pyramid.build(image.view());
  EXPECT_FALSE(init.addFrame(pyramid, 1.0));
  EXPECT_TRUE(init.failed());
  EXPECT_EQ(init.failure(), InitFailure::kNotFinite);
}

TEST(CoarseInitializer, TexturelessReferenceIsRefusedAndNextFrameRestarts) {
  const PinholeIntrinsics K = makeIntrinsics(320, 240, 250);
  CoarseInitializer init(PyramidCamera(K, 5));
  EXPECT_FALSE(init.addFrame(flatPyramid(K.width, K.height, 120.f), 1.0));
  EXPECT_TRUE(init.failed());
  EXPECT_EQ(init.failure(), InitFailure::kTooFewPoints);
  EXPECT_FALSE(init.addFrame(renderPyramid(init_test::wallAndFloorScene(), SE3d(), K), 1.0));
  EXPECT_EQ(init.status(), InitStatus::kWaitingForParallax);
  EXPECT_EQ(init.failure(), InitFailure::kNone);
  EXPECT_EQ(init.framesTracked(), 0);
}

TEST(CoarseInitializer, UnrelatedImageFailsTrackingAndResetStartsOver) {
  const PinholeIntrinsics K = makeIntrinsics(320, 240, 250);
  CoarseInitializer init(PyramidCamera(K, 5));
  init.addFrame(renderPyramid(init_test::wallAndFloorScene(), SE3d(), K), 1.0);
  init.addFrame(renderPyramid(init_test::wallAndFloorScene(), SE3d(SO3d(), {0.01, 0, 0}), K), 1.0);
  ASSERT_EQ(init.status(), InitStatus::kWaitingForParallax);
  EXPECT_EQ(init.framesTracked(), 1);

  // A different scene: most points cannot be matched.
  init_test::InitScene other;
  other.addPlane({0, 0, 2.0}, {0, 0, -1}, 99U);
  EXPECT_FALSE(init.addFrame(renderPyramid(other, SE3d(), K), 1.0));
  EXPECT_TRUE(init.failed());
  EXPECT_TRUE(init.failure() == InitFailure::kLostTrack ||
              init.failure() == InitFailure::kResidualTooLarge)
      << toString(init.failure());

  // The next frame becomes the new reference.
  EXPECT_FALSE(init.addFrame(renderPyramid(other, SE3d(), K), 1.0));
  EXPECT_EQ(init.status(), InitStatus::kWaitingForParallax);
  EXPECT_EQ(init.framesTracked(), 0);

  init.addFrame(renderPyramid(other, SE3d(SO3d(), {0.01, 0, 0}), K), 1.0);
  EXPECT_EQ(init.framesTracked(), 1);
  init.reset();
  EXPECT_EQ(init.status(), InitStatus::kNoReference);
  EXPECT_EQ(init.framesTracked(), 0);
}

}  // namespace
}  // namespace ldsm
