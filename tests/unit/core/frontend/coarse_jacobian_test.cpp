// The coarse tracker's residual Jacobian w.r.t. [rho, phi, a, b] against central differences, and
// the normal-equation accumulation against a plain double-precision sum.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "frontend/coarse_residuals.h"
#include "frontend/coarse_tracker.h"
#include "track_scene.h"

namespace ldsm {
namespace {

using test::TrackScene;

// On a frame whose intensity is linear in the pixel coordinates, bilinear interpolation and the
// central-difference gradient are exact, so the analytic Jacobian must match numeric
// differentiation of the residual to rounding. With a radial distortion k the frame is sampled
// through it, and the Jacobian carries the distortion's own Jacobian.
void expectJacobianMatchesNumericDifferentiation(float radial_k) {
  const TrackScene scene;
  ImageF ref_image, ref_idepth;
  scene.render(SE3d(), ref_image, &ref_idepth);
  const ImagePyramid ref = test::makePyramid(ref_image);
  ImageF ramp(TrackScene::kWidth, TrackScene::kHeight);
  for (int y = 0; y < ramp.height(); ++y) {
    for (int x = 0; x < ramp.width(); ++x) ramp(x, y) = 20.f + 0.31f * x + 0.47f * y;
  }
  const ImagePyramid frame = test::makePyramid(ramp);

  CoarseTracker tracker(TrackScene::kWidth, TrackScene::kHeight, TrackScene::kLevels,
                        CoarseTrackerSettings());
  tracker.setReference(ref, scene.camera(), test::selectPoints(ref_image, ref_idepth), 1.3,
                       AffineLight{0.1, 3.0}, nullptr, radial_k);
  const double exposure = 0.8;
  SE3d::Tangent x;
  x << 0.04, -0.03, 0.05, 0.02, -0.03, 0.01;
  const SE3d T = SE3d::exp(x);
  const AffineLight affine{-0.2, 7.0};

  // Residual as a function of the 8 parameters (left perturbation of the pose).
  const auto residualAt = [&](const Eigen::Matrix<double, 8, 1>& d, int level, int index,
                              float* r) {
    const SE3d Td = SE3d::exp(d.head<6>()) * T;
    const AffineLight ad{affine.a + d(6), affine.b + d(7)};
    return tracker.pointResidual(frame, exposure, Td, ad, level, index, r, nullptr);
  };
  // Steps large enough that float rounding of the residual (~1e-5) stays well below tolerance.
  const double steps[8] = {1e-2, 1e-2, 1e-2, 2e-3, 2e-3, 2e-3, 1e-2, 1e-1};
  int checked = 0;
  for (int level = 0; level < TrackScene::kLevels; ++level) {
    const int count = tracker.depthMaps().points(level).count;
    for (int index = 0; index < count; index += std::max(1, count / 40)) {
      float r0, J[8];
      if (!tracker.pointResidual(frame, exposure, T, affine, level, index, &r0, J)) continue;
      for (int k = 0; k < 8; ++k) {
        Eigen::Matrix<double, 8, 1> d = Eigen::Matrix<double, 8, 1>::Zero();
        d(k) = steps[k];
        float rp, rm;
        if (!residualAt(d, level, index, &rp) || !residualAt(-d, level, index, &rm)) continue;
        const double numeric = (static_cast<double>(rp) - rm) / (2 * steps[k]);
        EXPECT_NEAR(J[k], numeric, 5e-3 + 2e-3 * std::abs(numeric))
            << "level " << level << " point " << index << " parameter " << k;
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 8 * 100);
}

TEST(CoarseJacobianTest, MatchesNumericDifferentiation) {
  expectJacobianMatchesNumericDifferentiation(0.f);
}

TEST(CoarseJacobianTest, MatchesNumericDifferentiationThroughARadialDistortion) {
  expectJacobianMatchesNumericDifferentiation(0.15f);
  expectJacobianMatchesNumericDifferentiation(-0.1f);
}

TEST(CoarseJacobianTest, ResidualUsesTheAffineModel) {
  // Identity pose: r = I_frame - (exp(a - a_ref) e / e_ref (I_ref - b_ref) + b).
  const TrackScene scene;
  ImageF image, idepth;
  scene.render(SE3d(), image, &idepth);
  const ImagePyramid pyramid = test::makePyramid(image);
  CoarseTracker tracker(TrackScene::kWidth, TrackScene::kHeight, TrackScene::kLevels,
                        CoarseTrackerSettings());
  const AffineLight ref_affine{0.2, 4.0};
  tracker.setReference(pyramid, scene.camera(), test::selectPoints(image, idepth), 2.0, ref_affine);
  const AffineLight affine{-0.1, 6.0};
  const LevelPoints& pts = tracker.depthMaps().points(0);
  const double scale = std::exp(affine.a - ref_affine.a) * 1.5 / 2.0;
  for (int i = 0; i < pts.count; i += 97) {
    float r;
    if (!tracker.pointResidual(pyramid, 1.5, SE3d(), affine, 0, i, &r, nullptr))
      continue;  // border
    const double expected =
        pts.intensity[i] - (scale * (pts.intensity[i] - ref_affine.b) + affine.b);
    EXPECT_NEAR(r, expected, 1e-3);
  }
}

TEST(CoarseNormalEquationsTest, MatchesDoubleSum) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  WarpedResiduals w;
  const int n = 1000;
  w.allocate(n);
  w.count = n;
  CoarseMatrix H_ref = CoarseMatrix::Zero();
  CoarseVector g_ref = CoarseVector::Zero();
  for (int i = 0; i < n; ++i) {
    w.dx_fx[i] = 300 * u(rng);
    w.dy_fy[i] = 300 * u(rng);
    w.nx[i] = 0.6f * u(rng);
    w.ny[i] = 0.5f * u(rng);
    w.iz[i] = 0.3f + 0.2f * u(rng);
    w.ref_term[i] = 128 + 100 * u(rng);
    w.residual[i] = 10 * u(rng);
    w.weight[i] = 0.5f + 0.5f * u(rng);
    float J[8];
    coarseJacobianRow(w.dx_fx[i], w.dy_fy[i], w.nx[i], w.ny[i], w.iz[i], w.ref_term[i], J);
    const Eigen::Matrix<double, 8, 1> j = Eigen::Map<Eigen::Matrix<float, 8, 1>>(J).cast<double>();
    H_ref += w.weight[i] * j * j.transpose();
    g_ref += w.weight[i] * w.residual[i] * j;
  }
  CoarseMatrix H;
  CoarseVector g;
  accumulateNormalEquations(w, H, g);
  EXPECT_LT((H - H_ref).norm(), 1e-5 * H_ref.norm());
  EXPECT_LT((g - g_ref).norm(), 1e-5 * g_ref.norm());
  EXPECT_TRUE(H.isApprox(H.transpose()));
}

}  // namespace
}  // namespace ldsm
