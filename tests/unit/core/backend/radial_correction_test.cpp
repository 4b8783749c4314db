#include "backend/radial_correction.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <random>

namespace ldsm {
namespace {

TEST(RadialCorrection, RemoveInvertsApply) {
  for (float k : {-0.1f, -0.02f, 0.f, 0.015f, 0.1f})
    for (float x = -1.2f; x <= 1.2f; x += 0.3f)
      for (float y = -0.9f; y <= 0.9f; y += 0.3f) {
        const Eigen::Vector2f d = applyRadial(k, x, y);
        const Eigen::Vector2f u = removeRadial(k, d.x(), d.y());
        EXPECT_NEAR(u.x(), x, 2e-5f) << "k " << k;
        EXPECT_NEAR(u.y(), y, 2e-5f) << "k " << k;
      }
}

TEST(RadialCorrection, RayAndProjectionAreInverse) {
  PinholeIntrinsics K{300, 310, 160, 118, 320, 240};
  const LevelCamera cam = PyramidCamera(K, 1)[0];
  const float k = 0.03f;
  const Eigen::Vector3f ray = radialRay(cam, k, 301.f, 12.f);
  const Eigen::Vector2f px = radialProject(cam, k, 2.5f * ray);
  EXPECT_NEAR(px.x(), 301.f, 1e-3f);
  EXPECT_NEAR(px.y(), 12.f, 1e-3f);
  // Outward: the pinhole ray of a border pixel is further out than the distorted one for k > 0.
  EXPECT_LT(std::abs(ray.x()), std::abs(cam.unproject(301.f, 12.f).x()));
}

TEST(RadialCorrection, EnvelopeStepIsTheKComponentOfTheFullSolve) {
  // A random positive definite system over 8 frame parameters, 5 depths and k.
  std::mt19937 rng(3);
  std::normal_distribution<double> N(0.0, 1.0);
  const int nf = 8, nd = 5, n = nf + nd + 1;
  Eigen::MatrixXd J(40, n);
  for (int i = 0; i < J.rows(); ++i)
    for (int j = 0; j < n; ++j) J(i, j) = N(rng);
  const Eigen::MatrixXd H = J.transpose() * J;
  Eigen::VectorXd g(n);
  for (int i = 0; i < n; ++i) g[i] = N(rng);
  // Depths are not coupled to each other: keep the block diagonal.
  Eigen::MatrixXd Hd = H;
  for (int a = nf; a < nf + nd; ++a)
    for (int b = nf; b < nf + nd; ++b)
      if (a != b) Hd(a, b) = 0.0;
  Hd += 1e-3 * Eigen::MatrixXd::Identity(n, n);
  const Eigen::VectorXd full = Hd.ldlt().solve(-g);

  RadialTerms terms;
  terms.reset(nf);
  terms.H_fk = Hd.block(0, nf + nd, nf, 1);
  terms.H_kk = Hd(n - 1, n - 1);
  terms.b_k = g[n - 1];
  std::vector<double> H_dd, b_d;
  for (int i = 0; i < nd; ++i) {
    H_dd.push_back(Hd(nf + i, nf + i));
    b_d.push_back(g[nf + i]);
    terms.H_dk.push_back(Hd(nf + i, n - 1));
  }
  double step = 0, curvature = 0;
  ASSERT_TRUE(radialEnvelopeStep(Hd.topLeftCorner(nf, nf), g.head(nf), Hd.block(0, nf, nf, nd),
                                 H_dd, b_d, terms, &step, &curvature));
  EXPECT_NEAR(step, full[n - 1], 1e-6 * (1.0 + std::abs(full[n - 1])));
  // The curvature is 1 / (H^-1)_kk.
  const double inv_kk = Hd.inverse()(n - 1, n - 1);
  EXPECT_NEAR(curvature, 1.0 / inv_kk, 1e-6 / inv_kk);

  // Mismatched sizes and an undefined curvature are refused.
  terms.H_dk.pop_back();
  EXPECT_FALSE(radialEnvelopeStep(Hd.topLeftCorner(nf, nf), g.head(nf), Hd.block(0, nf, nf, nd),
                                  H_dd, b_d, terms, &step, &curvature));
  RadialTerms empty;
  empty.reset(nf);
  EXPECT_FALSE(radialEnvelopeStep(Hd.topLeftCorner(nf, nf), g.head(nf), Eigen::MatrixXd(nf, 0), {},
                                  {}, empty, &step, &curvature));
  EXPECT_EQ(step, 0.0);
}

TEST(RadialRefinement, ConvergesToAConsistentMeasurement) {
  CalibrationRefinementConfig c;
  RadialRefinement r(c);
  // Every window says k is 0.02 away from what is applied, as a window with k unmodelled does.
  for (int i = 0; i < 200; ++i) r.addWindowStep(0.02 - r.applied(), 1.0);
  EXPECT_TRUE(r.engaged());
  EXPECT_NEAR(r.estimate(), 0.02, 1e-4);
  EXPECT_DOUBLE_EQ(r.applied(), r.estimate());
  EXPECT_EQ(r.windows(), 200);
}

TEST(RadialRefinement, StaysOffInsideTheDeadBandAndSwitchesWithHysteresis) {
  CalibrationRefinementConfig c;
  c.radial_dead_band = 0.004;
  RadialRefinement r(c);
  for (int i = 0; i < 100; ++i) r.addWindowStep(0.003 - r.applied(), 1.0);
  EXPECT_FALSE(r.engaged());
  EXPECT_EQ(r.applied(), 0.0);
  EXPECT_NEAR(r.estimate(), 0.003, 1e-4);
  for (int i = 0; i < 100; ++i) r.addWindowStep(0.006 - r.applied(), 1.0);
  EXPECT_TRUE(r.engaged());
  EXPECT_NEAR(r.applied(), 0.006, 1e-4);
  // Back to 0.003: above half the band, the correction stays on.
  for (int i = 0; i < 100; ++i) r.addWindowStep(0.003 - r.applied(), 1.0);
  EXPECT_TRUE(r.engaged());
  EXPECT_NEAR(r.applied(), 0.003, 1e-4);
  for (int i = 0; i < 100; ++i) r.addWindowStep(0.0 - r.applied(), 1.0);
  EXPECT_FALSE(r.engaged());
  EXPECT_EQ(r.applied(), 0.0);
}

TEST(RadialRefinement, WeighsWindowsByCurvature) {
  CalibrationRefinementConfig c;
  c.radial_memory = 1.0;
  RadialRefinement r(c);
  // The first window weighs 1 against a starting weight of 4 at k = 0: estimate 0.01 / 5.
  r.addWindowStep(0.01, 1.0);
  EXPECT_NEAR(r.estimate(), 0.002, 1e-12);
  // A window with 15 times the information against the weight 5 so far (0.002 is inside the
  // dead band, so the step was taken at k = 0).
  r.addWindowStep(0.04, 15.0);
  EXPECT_NEAR(r.estimate(), 0.002 + 0.75 * 0.038, 1e-12);
}

TEST(RadialRefinement, IgnoresBadInputClampsAndCanBeTurnedOff) {
  CalibrationRefinementConfig c;
  c.radial_max = 0.05;
  RadialRefinement r(c);
  r.addWindowStep(std::numeric_limits<double>::quiet_NaN(), 1.0);
  r.addWindowStep(0.1, 0.0);
  r.addWindowStep(0.1, -1.0);
  r.addWindowStep(0.1, std::numeric_limits<double>::infinity());
  EXPECT_EQ(r.windows(), 0);
  EXPECT_EQ(r.estimate(), 0.0);
  for (int i = 0; i < 100; ++i) r.addWindowStep(1.0, 1.0);
  EXPECT_DOUBLE_EQ(r.estimate(), 0.05);
  EXPECT_DOUBLE_EQ(r.applied(), 0.05);

  c.refine_radial = false;
  RadialRefinement off(c);
  for (int i = 0; i < 10; ++i) off.addWindowStep(0.02, 1.0);
  EXPECT_EQ(off.windows(), 0);
  EXPECT_EQ(off.applied(), 0.0);
}

}  // namespace
}  // namespace ldsm
