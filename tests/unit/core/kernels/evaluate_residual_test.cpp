// evaluateResidual (SIMD sampling and lane-wise pair accumulation) against the scalar path: the
// straightforward per-pixel evaluation with full Jacobian rows summed in double. Energies, pair
// blocks (H, b), couplings and depth terms agree to relative 1e-5 of their magnitude (the sum of
// their terms' absolute values; see ScalarTerms).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <random>
#include <vector>

#include "backend/photometric_residual.h"
#include "image/interpolation.h"
#include "plane_scene.h"

namespace ldsm {
namespace {

constexpr int kW = 320, kH = 240;
constexpr double kFx = 280, kFy = 260, kCx = 159.5, kCy = 119.5;
constexpr double kTol = 1e-5;

struct ScalarTerms {
  float energy = 0.f;
  ResidualState state = ResidualState::OutOfBounds;
  RelMatrix H = RelMatrix::Zero();
  RelVector b = RelVector::Zero();
  RelVector coupling = RelVector::Zero();
  double H_dd = 0.0, b_d = 0.0;
  // Magnitudes: the same sums over the terms' absolute values, which bound the rounding. The
  // residual r = I_t - scale I_h - offset is a difference of terms of magnitude
  // R = |I_t| + |scale I_h| + |offset|; J_d = gx dx/dd + gy dy/dd is one of magnitude
  // |gx| |dx/dd|_mag + |gy| |dy/dd|_mag (dx/dd itself is a difference of two terms).
  double energy_mag = 0.0;
  double H_dd_mag = 0.0;
  RelMatrix H_mag = RelMatrix::Zero();
  RelVector b_mag = RelVector::Zero();
  RelVector coupling_mag = RelVector::Zero();
  double b_d_mag = 0.0;
};

/// The scalar path: per pattern pixel, project (the centre's K R K^-1 (u, v, 1) + K t d plus the
/// offset's image K R K^-1 (du, dv, 0), as the kernel does, so that the two differ only in the
/// order of float sums), sample, weight, and add w J^T J of the full 11-entry row in double.
void scalarResidual(const ActivePoint& point, const FramePairPrecalc& pair,
                    const ResidualSettings& settings, ScalarTerms& out) {
  const LevelCamera& cam = pair.cam;
  const int w = pair.target_image.width, h = pair.target_image.height;
  const float d = point.idepth;
  const Eigen::Vector3f pc = pair.KRKi * Eigen::Vector3f(point.u, point.v, 1.f) + pair.Kt * d;
  if (!(pc.z() > 0.f) || !isInsideForBilinear(pc.x() / pc.z(), pc.y() / pc.z(), w, h,
                                              settings.border + kPatternPadding))
    return;
  const Eigen::Vector3f ray = cam.unproject(point.u, point.v);
  const Eigen::Vector3f p = pair.R0 * ray / d + pair.t0;
  const float zi = 1.f / p.z();
  Eigen::Matrix<float, 2, 3> dpx_dp;
  dpx_dp << cam.fx * zi, 0.f, -cam.fx * p.x() * zi * zi, 0.f, cam.fy * zi,
      -cam.fy * p.y() * zi * zi;
  Eigen::Matrix<float, 3, 6> dp_deps;
  dp_deps << 1.f, 0.f, 0.f, 0.f, p.z(), -p.y(), 0.f, 1.f, 0.f, -p.z(), 0.f, p.x(), 0.f, 0.f, 1.f,
      p.y(), -p.x(), 0.f;
  const Eigen::Matrix<float, 2, 6> dpx_deps = dpx_dp * dp_deps;
  // dpx/dp * dp/dd, dp/dd = -(p - t0) / d, in the form without cancellation (q = d p).
  const Eigen::Vector3f qd = pair.R0 * ray + pair.t0 * d;
  const Eigen::Vector2f dpx_dd(cam.fx / qd.z() * (pair.t0.x() - qd.x() / qd.z() * pair.t0.z()),
                               cam.fy / qd.z() * (pair.t0.y() - qd.y() / qd.z() * pair.t0.z()));

  const float c = settings.gradient_weight_c, th = settings.huber_threshold;
  const Eigen::Vector2f dpx_dd_mag(
      cam.fx / qd.z() * (std::fabs(pair.t0.x()) + std::fabs(qd.x() / qd.z() * pair.t0.z())),
      cam.fy / qd.z() * (std::fabs(pair.t0.y()) + std::fabs(qd.y() / qd.z() * pair.t0.z())));
  Eigen::Matrix<double, 11, 1> J[kPatternSize], Jm[kPatternSize];
  // The centre's projection with the kernel's order of operations: a one-ulp difference in a
  // pixel position changes the sampled values by gradient x ulp, far above summation rounding.
  const float* K = pair.KRKi.data();
  const Eigen::Vector3f centre(K[0] * point.u + K[3] * point.v + K[6] + pair.Kt[0] * d,
                               K[1] * point.u + K[4] * point.v + K[7] + pair.Kt[1] * d,
                               K[2] * point.u + K[5] * point.v + K[8] + pair.Kt[2] * d);
  double wk[kPatternSize], rk[kPatternSize], Rk[kPatternSize];
  float energy = 0.f;
  for (int k = 0; k < kPatternSize; ++k) {
    const float ox = static_cast<float>(kPatternOffsets[k][0]);
    const float oy = static_cast<float>(kPatternOffsets[k][1]);
    const Eigen::Vector3f q = centre + ox * pair.KRKi.col(0) + oy * pair.KRKi.col(1);
    const float x = q.x() / q.z(), y = q.y() / q.z();
    if (!(q.z() > 0.f) || !isInsideForBilinear(x, y, w, h, settings.border)) return;
    const GradientPixel g = interpolateBilinear(pair.target_image, x, y);
    const float r = g.intensity - pair.scale * point.colors[k] - pair.offset;
    const float gw = 0.5f * (gradientWeightSqrt(g.dx, g.dy, c) + point.grad_weights[k]);
    const float ar = std::fabs(r);
    energy += gw * gw * (ar < th ? r * r : 2.f * th * ar - th * th);
    Rk[k] =
        std::fabs(g.intensity) + std::fabs(pair.scale * point.colors[k]) + std::fabs(pair.offset);
    out.energy_mag += gw * gw * 2.0 * ar * (Rk[k] + ar);
    wk[k] = gw * gw * (ar < th ? 1.f : th / ar);
    rk[k] = r;
    for (int j = 0; j < 6; ++j) J[k][j] = g.dx * dpx_deps(0, j) + g.dy * dpx_deps(1, j);
    J[k][6] = pair.scale * (point.colors[k] - pair.host_b);
    J[k][7] = pair.scale;
    J[k][8] = -J[k][6];
    J[k][9] = -1.0;
    J[k][10] = g.dx * dpx_dd.x() + g.dy * dpx_dd.y();
    for (int j = 0; j < 6; ++j)
      Jm[k][j] = std::fabs(g.dx * dpx_deps(0, j)) + std::fabs(g.dy * dpx_deps(1, j));
    Jm[k].segment<4>(6) = J[k].segment<4>(6).cwiseAbs();
    Jm[k][10] = std::fabs(g.dx) * dpx_dd_mag.x() + std::fabs(g.dy) * dpx_dd_mag.y();
  }
  out.energy = energy;
  out.state =
      energy > outlierEnergy(pair, settings) ? ResidualState::Outlier : ResidualState::Inlier;
  if (out.state != ResidualState::Inlier) return;
  for (int k = 0; k < kPatternSize; ++k) {
    const Eigen::Matrix<double, 10, 1> Jr = J[k].head<10>();
    out.H += wk[k] * Jr * Jr.transpose();
    out.b += wk[k] * rk[k] * Jr;
    out.coupling += wk[k] * J[k][10] * Jr;
    out.H_dd += wk[k] * J[k][10] * J[k][10];
    out.b_d += wk[k] * J[k][10] * rk[k];
    const Eigen::Matrix<double, 10, 1> Ja = Jm[k].head<10>();
    const double jdm = Jm[k][10];
    const double R = Rk[k] + std::fabs(rk[k]);
    out.H_mag += wk[k] * Ja * Ja.transpose();
    out.b_mag += wk[k] * R * Ja;
    out.coupling_mag += wk[k] * jdm * Ja;
    out.H_dd_mag += wk[k] * jdm * jdm;
    out.b_d_mag += wk[k] * jdm * R;
  }
}

struct Scene {
  std::vector<std::unique_ptr<WindowKeyframe>> frames;
  std::vector<std::unique_ptr<ActivePoint>> points;
  LevelCamera cam;
};

/// Two keyframes of the wall-and-floor scene with affine brightness, exposures and a pose that
/// differs from its linearisation point; noisy depths so that residuals are not zero.
Scene makeScene() {
  Scene s;
  s.cam = PyramidCamera(PinholeIntrinsics{kFx, kFy, kCx, kCy, kW, kH}, 3)[0];
  const test::PlaneScene scene = test::PlaneScene::wallAndFloor(4.0);
  std::vector<ImageF> idepths(2);
  for (int i = 0; i < 2; ++i) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(0.15 * i, 0.03 * i, 0.1 * i);
    T.linear() = Eigen::AngleAxisd(0.02 * i, Eigen::Vector3d::UnitY()).toRotationMatrix();
    ImageF img = scene.render(T, kFx, kFy, kCx, kCy, kW, kH, &idepths[i]);
    if (i == 1) {  // brighter, roughly as the affine parameters below predict (scale 1.38)
      for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) img(x, y) = 1.37f * img(x, y) - 6.f;
    }
    auto pyr = std::make_unique<ImagePyramid>(kW, kH, 3);
    pyr->build(img.view());
    auto kf = std::make_unique<WindowKeyframe>(i, i, 0.1 * i, i == 0 ? 10.0 : 13.0, std::move(pyr));
    const SE3d T_c_w = SE3d(Eigen::Matrix3d(T.linear()), T.translation()).inverse();
    kf->setInitialState(T_c_w, AffineLight{0.05 * i, 3.0 - 5.0 * i});
    s.frames.push_back(std::move(kf));
  }
  Eigen::Matrix<double, 6, 1> step;
  step << 0.004, -0.003, 0.002, 0.001, -0.002, 0.0015;
  s.frames[1]->T_c_w = SE3d::exp(step) * s.frames[1]->T_c_w;  // current != linearisation point
  s.frames[1]->aff.a += 0.01;
  std::mt19937 rng(1);
  std::normal_distribution<float> N(0.f, 1.f);
  for (int y = 10; y < kH - 10; y += 5)
    for (int x = 10; x < kW - 10; x += 5) {
      const float d = idepths[0](x, y);
      if (d <= 0.f) continue;
      auto p = std::make_unique<ActivePoint>();
      const float fx = static_cast<float>(x) + 0.3f * N(rng), fy = static_cast<float>(y);
      if (!initActivePoint(*p, *s.frames[0], fx, fy, d * (1.f + 0.05f * N(rng)), 50.f)) continue;
      p->residuals.push_back({s.frames[1].get()});
      s.points.push_back(std::move(p));
    }
  return s;
}

void expectMatchesScalarPath(bool compacted_target) {
  Scene s = makeScene();
  // A keyframe that is no longer the newest is sampled from its 16-bit level 0.
  if (compacted_target) s.frames[1]->compactPyramid(true);
  FramePairPrecalc pair;
  pair.set(*s.frames[0], *s.frames[1], s.cam);
  ASSERT_EQ(pair.target_image.isCompact(), compacted_target);
  ResidualSettings settings;
  PairAccumulator pair_acc;
  pair_acc.reset();
  ScalarTerms total;
  int counts[3] = {0, 0, 0};
  for (auto& p : s.points) {
    ScalarTerms ref;
    scalarResidual(*p, pair, settings, ref);
    ResidualAccumulator acc;
    acc.pair = &pair_acc;
    PointResidual& res = p->residuals[0];
    const float e = evaluateResidual(*p, res, pair, settings, &acc);
    ASSERT_EQ(res.state, ref.state) << p->u << " " << p->v;
    ++counts[static_cast<int>(res.state)];
    if (res.state == ResidualState::OutOfBounds) continue;
    ASSERT_NEAR(e, ref.energy, kTol * ref.energy_mag + 1e-6);
    ASSERT_EQ(res.energy, e);
    if (res.state != ResidualState::Inlier) continue;
    total.H += ref.H;
    total.b += ref.b;
    total.H_mag += ref.H_mag;
    total.b_mag += ref.b_mag;
    ASSERT_NEAR(acc.H_dd, ref.H_dd, kTol * ref.H_dd_mag);
    ASSERT_NEAR(acc.b_d, ref.b_d, kTol * ref.b_d_mag);
    for (int i = 0; i < kRelParams; ++i)
      ASSERT_NEAR(acc.coupling[i], ref.coupling[i], kTol * ref.coupling_mag[i]) << i;
  }
  EXPECT_GT(counts[0], 500);  // inliers
  EXPECT_GT(counts[2], 20);   // out of bounds
  EXPECT_EQ(pair_acc.count(), counts[0]);
  RelMatrix H;
  RelVector b;
  pair_acc.reduce(pair, H, b);
  for (int i = 0; i < kRelParams; ++i) {
    for (int j = 0; j < kRelParams; ++j)
      ASSERT_NEAR(H(i, j), total.H(i, j), kTol * total.H_mag(i, j)) << i << "," << j;
    ASSERT_NEAR(b[i], total.b[i], kTol * total.b_mag[i]) << i;
  }
}

TEST(EvaluateResidual, MatchesScalarPath) {
  expectMatchesScalarPath(false);
}

TEST(EvaluateResidual, MatchesScalarPathOnACompactedTarget) {
  expectMatchesScalarPath(true);
}

// A keyframe that is no longer the newest keeps its level-0 intensities alone: its residuals,
// Jacobians and sums are the same bits as before it was compacted.
TEST(EvaluateResidual, ACompactedTargetGivesTheSameBits) {
  Scene s = makeScene();
  ResidualSettings settings;
  const auto evaluateAll = [&](std::vector<float>& energies, std::vector<double>& sums) {
    FramePairPrecalc pair;
    pair.set(*s.frames[0], *s.frames[1], s.cam);
    PairAccumulator pair_acc;
    pair_acc.reset();
    for (auto& p : s.points) {
      ResidualAccumulator acc;
      acc.pair = &pair_acc;
      energies.push_back(evaluateResidual(*p, p->residuals[0], pair, settings, &acc));
      energies.push_back(static_cast<float>(p->residuals[0].state));
      sums.push_back(acc.H_dd);
      sums.push_back(acc.b_d);
      for (int i = 0; i < kRelParams; ++i) sums.push_back(acc.coupling[i]);
    }
    RelMatrix H;
    RelVector b;
    pair_acc.reduce(pair, H, b);
    sums.insert(sums.end(), H.data(), H.data() + H.size());
    sums.insert(sums.end(), b.data(), b.data() + b.size());
    return pair.target_image.isIntensity();
  };
  std::vector<float> e_full, e_compacted;
  std::vector<double> s_full, s_compacted;
  EXPECT_FALSE(evaluateAll(e_full, s_full));
  s.frames[1]->compactPyramid(false);
  EXPECT_TRUE(evaluateAll(e_compacted, s_compacted));
  ASSERT_EQ(e_full.size(), e_compacted.size());
  ASSERT_EQ(s_full.size(), s_compacted.size());
  EXPECT_EQ(std::memcmp(e_full.data(), e_compacted.data(), e_full.size() * sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(s_full.data(), s_compacted.data(), s_full.size() * sizeof(double)), 0);
}

TEST(EvaluateResidual, EitherKeyframesAdaptedThresholdDecides) {
  Scene s = makeScene();
  ResidualSettings settings;
  FramePairPrecalc pair;
  pair.set(*s.frames[0], *s.frames[1], s.cam);
  // A residual with clearly positive energy, an inlier under the fixed threshold.
  PointResidual* res = nullptr;
  ActivePoint* point = nullptr;
  float e = 0.f;
  for (auto& p : s.points) {
    PointResidual& r = p->residuals[0];
    const float ep = evaluateResidual(*p, r, pair, settings, nullptr);
    if (r.state == ResidualState::Inlier && ep > 1.f) {
      res = &r;
      point = p.get();
      e = ep;
      break;
    }
  }
  ASSERT_NE(res, nullptr);
  s.frames[0]->outlier_energy = 0.5f * e;  // the host's threshold adapted below it
  pair.set(*s.frames[0], *s.frames[1], s.cam);
  evaluateResidual(*point, *res, pair, settings, nullptr);
  EXPECT_EQ(res->state, ResidualState::Outlier);
  s.frames[1]->outlier_energy = 2.f * e;  // the target's is higher: the larger one counts
  pair.set(*s.frames[0], *s.frames[1], s.cam);
  evaluateResidual(*point, *res, pair, settings, nullptr);
  EXPECT_EQ(res->state, ResidualState::Inlier);
}

TEST(EvaluateResidual, DepthOnlyMatchesScalarPath) {
  Scene s = makeScene();
  FramePairPrecalc pair;
  pair.set(*s.frames[0], *s.frames[1], s.cam);
  ResidualSettings settings;
  int inliers = 0;
  for (auto& p : s.points) {
    ScalarTerms ref;
    scalarResidual(*p, pair, settings, ref);
    ResidualAccumulator acc;
    acc.depth_only = true;
    evaluateResidual(*p, p->residuals[0], pair, settings, &acc);
    if (ref.state != ResidualState::Inlier) continue;
    ++inliers;
    ASSERT_NEAR(acc.H_dd, ref.H_dd, kTol * ref.H_dd_mag);
    ASSERT_NEAR(acc.b_d, ref.b_d, kTol * ref.b_d_mag);
  }
  EXPECT_GT(inliers, 500);
}

}  // namespace
}  // namespace ldsm
