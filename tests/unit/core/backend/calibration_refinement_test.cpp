#include "backend/calibration_refinement.h"

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

TEST(CalibrationEnvelope, StepIsTheCalibrationPartOfTheFullSolve) {
  // A random positive definite system over 8 frame parameters, 5 depths and the 4 calibration
  // parameters.
  std::mt19937 rng(3);
  std::normal_distribution<double> N(0.0, 1.0);
  const int nf = 8, nd = 5, nc = kCalibParams, n = nf + nd + nc;
  Eigen::MatrixXd J(60, n);
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

  CalibrationTerms terms;
  terms.reset(nf);
  terms.H_fc = Hd.block(0, nf + nd, nf, nc);
  terms.H_cc = Hd.bottomRightCorner(nc, nc);
  terms.b_c = g.tail(nc);
  std::vector<double> H_dd, b_d;
  for (int i = 0; i < nd; ++i) {
    H_dd.push_back(Hd(nf + i, nf + i));
    b_d.push_back(g[nf + i]);
    terms.H_dc.push_back(Hd.block(nf + i, nf + nd, 1, nc).transpose());
  }
  // Every subset of the parameters: the step is the full solve of the system without the others.
  for (int bits = 1; bits < (1 << nc); ++bits) {
    CalibMask mask{};
    std::vector<int> keep;
    for (int i = 0; i < nf + nd; ++i) keep.push_back(i);
    for (int p = 0; p < nc; ++p) {
      mask[static_cast<size_t>(p)] = (bits >> p) & 1;
      if (mask[static_cast<size_t>(p)]) keep.push_back(nf + nd + p);
    }
    const int m = static_cast<int>(keep.size());
    Eigen::MatrixXd Hs(m, m);
    Eigen::VectorXd gs(m);
    for (int i = 0; i < m; ++i) {
      gs[i] = g[keep[static_cast<size_t>(i)]];
      for (int j = 0; j < m; ++j)
        Hs(i, j) = Hd(keep[static_cast<size_t>(i)], keep[static_cast<size_t>(j)]);
    }
    const Eigen::VectorXd full = Hs.ldlt().solve(-gs);
    const Eigen::MatrixXd cov = Hs.inverse();
    CalibVector step;
    CalibMatrix curvature;
    ASSERT_TRUE(calibrationEnvelopeStep(Hd.topLeftCorner(nf, nf), g.head(nf),
                                        Hd.block(0, nf, nf, nd), H_dd, b_d, terms, mask, &step,
                                        &curvature));
    int at = nf + nd;
    for (int p = 0; p < nc; ++p) {
      if (!mask[static_cast<size_t>(p)]) {
        EXPECT_EQ(step[p], 0.0);
        EXPECT_EQ(curvature(p, p), 0.0);
        continue;
      }
      const int i = at;
      EXPECT_NEAR(step[p], full[i], 1e-6 * (1.0 + std::abs(full[i]))) << "mask " << bits;
      ++at;
    }
    // The curvature is the inverse of the calibration block of the covariance.
    const int mc = m - (nf + nd);
    const Eigen::MatrixXd info = cov.bottomRightCorner(mc, mc).inverse();
    int r = 0;
    for (int p = 0; p < nc; ++p) {
      if (!mask[static_cast<size_t>(p)]) continue;
      int c = 0;
      for (int q = 0; q < nc; ++q) {
        if (!mask[static_cast<size_t>(q)]) continue;
        EXPECT_NEAR(curvature(p, q), info(r, c), 1e-6 * (1.0 + std::abs(info(r, c))));
        ++c;
      }
      ++r;
    }
  }

  // Depths eliminated outside the coupling matrix (other_depths: the window's fixed points) give
  // the step and curvature of the same depths as columns.
  {
    const int kept = 3;  // depths 0-2 stay columns, 3 and 4 are summed into other_depths
    CalibrationTerms split;
    split.reset(nf);
    split.H_fc = terms.H_fc;
    split.H_cc = terms.H_cc;
    split.b_c = terms.b_c;
    std::vector<double> H_dd_kept(H_dd.begin(), H_dd.begin() + kept);
    std::vector<double> b_d_kept(b_d.begin(), b_d.begin() + kept);
    for (int i = 0; i < kept; ++i) split.H_dc.push_back(terms.H_dc[static_cast<size_t>(i)]);
    EliminatedDepthTerms& o = split.other_depths;
    for (int i = kept; i < nd; ++i) {
      const auto u = static_cast<size_t>(i);
      const Eigen::VectorXd c = Hd.block(0, nf + i, nf, 1);
      const double d = 1.0 / H_dd[u];
      o.A += c * c.transpose() * d;
      o.g += c * (b_d[u] * d);
      o.h += c * terms.H_dc[u].transpose() * d;
      o.hcc += terms.H_dc[u] * terms.H_dc[u].transpose() * d;
      o.bc += terms.H_dc[u] * (b_d[u] * d);
    }
    const CalibMask all{true, true, true, true};
    CalibVector step_all, step_split;
    CalibMatrix curvature_all, curvature_split;
    ASSERT_TRUE(calibrationEnvelopeStep(Hd.topLeftCorner(nf, nf), g.head(nf),
                                        Hd.block(0, nf, nf, nd), H_dd, b_d, terms, all, &step_all,
                                        &curvature_all));
    ASSERT_TRUE(calibrationEnvelopeStep(Hd.topLeftCorner(nf, nf), g.head(nf),
                                        Hd.block(0, nf, nf, kept), H_dd_kept, b_d_kept, split, all,
                                        &step_split, &curvature_split));
    for (int p = 0; p < nc; ++p) {
      EXPECT_NEAR(step_split[p], step_all[p], 1e-9 * (1.0 + std::abs(step_all[p])));
      for (int q = 0; q < nc; ++q)
        EXPECT_NEAR(curvature_split(p, q), curvature_all(p, q),
                    1e-9 * (1.0 + std::abs(curvature_all(p, q))));
    }
  }

  // Mismatched sizes, no parameter and an undefined curvature are refused.
  const CalibMask all{true, true, true, true};
  CalibVector step;
  CalibMatrix curvature;
  CalibrationTerms bad = terms;
  bad.H_dc.pop_back();
  EXPECT_FALSE(calibrationEnvelopeStep(Hd.topLeftCorner(nf, nf), g.head(nf),
                                       Hd.block(0, nf, nf, nd), H_dd, b_d, bad, all, &step,
                                       &curvature));
  EXPECT_FALSE(calibrationEnvelopeStep(Hd.topLeftCorner(nf, nf), g.head(nf),
                                       Hd.block(0, nf, nf, nd), H_dd, b_d, terms, CalibMask{},
                                       &step, &curvature));
  CalibrationTerms empty;
  empty.reset(nf);
  EXPECT_FALSE(calibrationEnvelopeStep(Hd.topLeftCorner(nf, nf), g.head(nf), Eigen::MatrixXd(nf, 0),
                                       {}, {}, empty, all, &step, &curvature));
  EXPECT_EQ(step.squaredNorm(), 0.0);
}

TEST(CalibrationEnvelope, CorrectedIntrinsicsScaleTheFocalLengthAndShiftThePrincipalPoint) {
  const PinholeIntrinsics base{300, 310, 160, 118, 320, 240};
  CalibVector c;
  c << 0.01, std::log(1.05), 3.0, -2.0;
  const PinholeIntrinsics k = correctedIntrinsics(base, c);
  EXPECT_NEAR(k.fx, 315.0, 1e-9);
  EXPECT_NEAR(k.fy, 325.5, 1e-9);
  EXPECT_DOUBLE_EQ(k.cx, 163.0);
  EXPECT_DOUBLE_EQ(k.cy, 116.0);
  EXPECT_EQ(k.width, 320);
  EXPECT_EQ(k.height, 240);
}

/// A radial-only refinement's step (the other parameters are not refined).
/// Radial only, without the significance test: these tests use curvatures of 1 (formal sigma 1
/// against corrections of 0.02), so they test the fusion, the bands and the hysteresis alone;
/// the significance test has its own tests below.
CalibrationRefinementConfig radialOnly() {
  CalibrationRefinementConfig c;
  c.refine_focal = false;
  c.refine_principal_point = false;
  c.radial_significance = 0.0;
  return c;
}

void addRadial(CalibrationRefinement& r, double step, double curvature) {
  CalibVector s = CalibVector::Zero();
  s[kCalibRadial] = step;
  CalibMatrix C = CalibMatrix::Zero();
  C(kCalibRadial, kCalibRadial) = curvature;
  r.addWindowStep(s, C);
}

double appliedK(const CalibrationRefinement& r) {
  return r.applied()[kCalibRadial];
}
double estimateK(const CalibrationRefinement& r) {
  return r.estimate()[kCalibRadial];
}

TEST(CalibrationRefinement, RadialConvergesToAConsistentMeasurement) {
  CalibrationRefinementConfig c = radialOnly();
  CalibrationRefinement r(c);
  // Every window says k is 0.02 away from what is applied, as a window with k unmodelled does.
  for (int i = 0; i < 200; ++i) addRadial(r, 0.02 - appliedK(r), 1.0);
  EXPECT_TRUE(r.engaged(kCalibRadial));
  EXPECT_NEAR(estimateK(r), 0.02, 1e-4);
  EXPECT_DOUBLE_EQ(appliedK(r), estimateK(r));
  EXPECT_EQ(r.windows(), 200);
}

// Settling (the keyframe rule takes keyframes more densely meanwhile): before any window, and while
// the applied correction moved by more than half its dead band over the last three windows.
TEST(CalibrationRefinement, SettlesUntilTheAppliedCorrectionStopsMoving) {
  CalibrationRefinementConfig c = radialOnly();
  c.settle_windows = 0.0;
  CalibrationRefinement r(c);
  EXPECT_TRUE(r.settling());  // nothing known yet
  // Windows that find the configured camera right: nothing is applied, nothing moves.
  addRadial(r, 0.0, 1.0);
  EXPECT_FALSE(r.settling());
  // A correction of 0.02 engages and converges geometrically (half way per window at first).
  int settling_windows = 0, last_settling = 0;
  for (int i = 1; i <= 60; ++i) {
    addRadial(r, 0.02 - appliedK(r), 1.0);
    if (r.settling()) {
      ++settling_windows;
      last_settling = i;
    }
  }
  EXPECT_TRUE(r.engaged(kCalibRadial));
  EXPECT_NEAR(appliedK(r), 0.02, 1e-3);
  EXPECT_GE(settling_windows, CalibrationRefinement::kQuietWindows);
  EXPECT_LT(last_settling, 60);
  // Settled, it stays so while the applied value moves by less than half the dead band per three
  // windows ...
  for (int i = 0; i < 10; ++i) {
    addRadial(r, 0.02 + 0.0001 * i - appliedK(r), 1.0);
    EXPECT_FALSE(r.settling()) << i;
  }
  // ... and a jump of the estimate makes it settle again, for as long as the jump lies within the
  // last three windows.
  addRadial(r, 0.05 - appliedK(r), 1e4);
  EXPECT_NEAR(appliedK(r), 0.05, 1e-3);
  EXPECT_TRUE(r.settling());
  for (int i = 1; i <= 5; ++i) {
    addRadial(r, 0.05 - appliedK(r), 1.0);
    EXPECT_EQ(r.settling(), i < CalibrationRefinement::kQuietWindows) << i;
  }
  // A parameter that is not refined never settles anything.
  CalibrationRefinementConfig none = radialOnly();
  none.refine_radial = false;
  EXPECT_FALSE(CalibrationRefinement(none).settling());
}

TEST(CalibrationRefinement, RadialStaysOffInsideTheDeadBandAndSwitchesWithHysteresis) {
  CalibrationRefinementConfig c = radialOnly();
  c.radial_dead_band = 0.004;
  CalibrationRefinement r(c);
  for (int i = 0; i < 100; ++i) addRadial(r, 0.003 - appliedK(r), 1.0);
  EXPECT_FALSE(r.engaged(kCalibRadial));
  EXPECT_EQ(appliedK(r), 0.0);
  EXPECT_NEAR(estimateK(r), 0.003, 1e-4);
  for (int i = 0; i < 100; ++i) addRadial(r, 0.006 - appliedK(r), 1.0);
  EXPECT_TRUE(r.engaged(kCalibRadial));
  EXPECT_NEAR(appliedK(r), 0.006, 1e-4);
  // Back to 0.003: above half the band, the correction stays on.
  for (int i = 0; i < 100; ++i) addRadial(r, 0.003 - appliedK(r), 1.0);
  EXPECT_TRUE(r.engaged(kCalibRadial));
  EXPECT_NEAR(appliedK(r), 0.003, 1e-4);
  for (int i = 0; i < 100; ++i) addRadial(r, 0.0 - appliedK(r), 1.0);
  EXPECT_FALSE(r.engaged(kCalibRadial));
  EXPECT_EQ(appliedK(r), 0.0);
}

TEST(CalibrationRefinement, RadialWeighsWindowsByCurvature) {
  CalibrationRefinementConfig c = radialOnly();
  c.memory = 1.0;
  c.settle_windows = 0.0;  // the fusion alone (the first window's estimate is applied)
  CalibrationRefinement r(c);
  // The first window weighs 1 against a starting weight of 1 at k = 0: estimate 0.01 / 2.
  addRadial(r, 0.01, 1.0);
  EXPECT_NEAR(estimateK(r), 0.005, 1e-12);
  // A window with 15 times the information against the weight 2 so far (0.005 is outside the
  // dead band, so the step was taken at k = 0.005: the measurement is 0.045).
  addRadial(r, 0.04, 15.0);
  EXPECT_NEAR(estimateK(r), 0.005 + 15.0 / 17.0 * 0.04, 1e-12);
}

// In the first windows a correction needs a wider band: after n windows the dead band times
// (1 + settle_windows / n). The estimate itself is fused as before; only applying it waits.
TEST(CalibrationRefinement, FirstWindowsNeedAWiderBandToApplyACorrection) {
  CalibrationRefinementConfig c = radialOnly();
  c.memory = 1.0;
  c.radial_dead_band = 0.003;
  c.settle_windows = 3.0;
  CalibrationRefinement r(c);
  // Each window measures k = 0.0045, 1.5 dead bands.
  int applied_at = 0;
  for (int n = 1; n <= 12; ++n) {
    addRadial(r, 0.0045 - appliedK(r), 1.0);
    if (applied_at == 0 && r.engaged(kCalibRadial)) applied_at = n;
    if (applied_at == 0) {
      EXPECT_EQ(appliedK(r), 0.0) << n;
    }
  }
  // The estimate (one starting window's weight at 0) is 0.0045 n / (n + 1): above 0.003 (1 + 3/n)
  // from n = 9 on (0.00405 against 0.0040; at n = 8 0.0040 against 0.004125).
  EXPECT_EQ(applied_at, 9);
  EXPECT_NEAR(appliedK(r), 0.0045 * 12.0 / 13.0, 1e-12);
  // A large error is applied at once: 0.03 measured, 0.015 estimated after one window > 0.012.
  CalibrationRefinement big(c);
  addRadial(big, 0.03, 1.0);
  EXPECT_TRUE(big.engaged(kCalibRadial));
  EXPECT_NEAR(appliedK(big), 0.015, 1e-12);
  // Without the settling band the small error is applied as soon as it leaves the dead band.
  c.settle_windows = 0.0;
  CalibrationRefinement eager(c);
  addRadial(eager, 0.005, 1.0);
  EXPECT_FALSE(eager.engaged(kCalibRadial)) << "0.0025 is inside the band";
  addRadial(eager, 0.005 - appliedK(eager), 1.0);
  EXPECT_TRUE(eager.engaged(kCalibRadial)) << "0.0033 after two windows";
}

// The realistic sigma: the fused formal one times sqrt(window overlap x the windows' mean squared
// innovation in units of their own formal sigma), never below sqrt(overlap) x the formal one.
TEST(CalibrationRefinement, RealisticSigmaScalesTheFormalOneByTheObservedScatterAndTheOverlap) {
  CalibrationRefinementConfig c = radialOnly();
  CalibrationRefinement r(c, 4);
  EXPECT_EQ(r.realisticSigma()[kCalibRadial], 0.0) << "no window yet";
  // One window, k step 0.01 at curvature 1e6 (formal sigma 0.001): 10 of its own sigmas from the
  // estimate 0, so the mean squared innovation is 100; the fused weight is (1 + memory) 1e6.
  addRadial(r, 0.01, 1e6);
  const double formal = 1.0 / std::sqrt((1.0 + c.memory) * 1e6);
  EXPECT_NEAR(r.sigma()[kCalibRadial], formal, 1e-15);
  EXPECT_NEAR(r.realisticSigma()[kCalibRadial], formal * std::sqrt(4.0 * 100.0), 1e-12);
  // Windows that agree with the estimate to well within their formal sigma: the factor is the
  // overlap alone.
  CalibrationRefinement quiet(c, 4);
  addRadial(quiet, 1e-5, 1e6);
  EXPECT_NEAR(quiet.realisticSigma()[kCalibRadial], 2.0 * quiet.sigma()[kCalibRadial], 1e-15);
}

// A correction whose windows scatter far more than their curvature says is not applied; a
// consistent one of the same size is.
TEST(CalibrationRefinement, ACorrectionMustStandOutOfTheWindowsScatter) {
  CalibrationRefinementConfig c = radialOnly();
  c.settle_windows = 0.0;
  c.radial_significance = 2.0;
  // Every window: formal sigma 0.001 (curvature 1e6); their mean k = 0.006, two dead bands.
  // Returns the first window after which the correction was applied (0: never).
  auto firstApplied = [&c](double scatter, CalibrationRefinement* out) {
    CalibrationRefinement r(c, 1);
    int first = 0;
    for (int n = 1; n <= 40; ++n) {
      const double measured = 0.006 + (n % 2 == 1 ? scatter : -scatter);
      addRadial(r, measured - appliedK(r), 1e6);
      if (first == 0 && r.engaged(kCalibRadial)) first = n;
    }
    *out = r;
    return first;
  };
  CalibrationRefinement r(c);
  // Consistent windows (half a formal sigma either side): applied within a few windows.
  const int consistent = firstApplied(0.0005, &r);
  EXPECT_GE(consistent, 1);
  EXPECT_LE(consistent, 3);
  EXPECT_NEAR(appliedK(r), 0.006, 5e-4);
  // Windows 30 formal sigmas either side of the same mean: the realistic sigma of the fused
  // estimate is about 30x the formal 0.00024 of 40 windows with memory 0.95, so 0.006 is under
  // one of them: never applied, although the estimate is outside its dead band.
  EXPECT_EQ(firstApplied(0.03, &r), 0);
  EXPECT_GT(std::abs(estimateK(r)), c.radial_dead_band);
  EXPECT_GT(r.realisticSigma()[kCalibRadial], 20.0 * r.sigma()[kCalibRadial]);
  // The same windows without the test: applied.
  c.radial_significance = 0.0;
  EXPECT_GE(firstApplied(0.03, &r), 1);
}

TEST(CalibrationRefinement, RadialIgnoresBadInputClampsAndCanBeTurnedOff) {
  CalibrationRefinementConfig c = radialOnly();
  c.radial_max = 0.05;
  CalibrationRefinement r(c);
  addRadial(r, std::numeric_limits<double>::quiet_NaN(), 1.0);
  addRadial(r, 0.1, 0.0);
  addRadial(r, 0.1, -1.0);
  addRadial(r, 0.1, std::numeric_limits<double>::infinity());
  EXPECT_EQ(r.windows(), 0);
  EXPECT_EQ(estimateK(r), 0.0);
  for (int i = 0; i < 100; ++i) addRadial(r, 1.0, 1.0);
  EXPECT_DOUBLE_EQ(estimateK(r), 0.05);
  EXPECT_DOUBLE_EQ(appliedK(r), 0.05);

  c.refine_radial = false;
  CalibrationRefinement off(c);
  for (int i = 0; i < 10; ++i) addRadial(off, 0.02, 1.0);
  EXPECT_EQ(off.windows(), 0);
  EXPECT_EQ(appliedK(off), 0.0);
}

TEST(CalibrationRefinement, FusesCorrelatedParametersWithTheirDeadBands) {
  CalibrationRefinementConfig c;
  c.refine_focal = true;
  c.refine_principal_point = true;
  CalibrationRefinement r(c);
  // The truth: focal 2 % long, cx 3 px, cy 0.5 px (inside its dead band), k 0. Each window
  // measures it with a different correlation between focal length and cx (as windows that turn
  // one way or the other do): the fused estimate reaches it, the uncertainty shrinks.
  CalibVector truth;
  truth << 0.0, 0.02, 3.0, 0.5;
  for (int i = 0; i < 300; ++i) {
    CalibMatrix C = CalibMatrix::Identity();
    C(1, 1) = 1e4;
    C(2, 2) = 0.5;
    C(1, 2) = C(2, 1) = (i % 2 == 0 ? 60.0 : -60.0);
    r.addWindowStep(truth - r.applied(), C);
  }
  EXPECT_NEAR(r.estimate()[kCalibFocal], 0.02, 1e-5);
  EXPECT_NEAR(r.estimate()[kCalibCx], 3.0, 1e-3);
  EXPECT_TRUE(r.engaged(kCalibFocal));
  EXPECT_TRUE(r.engaged(kCalibCx));
  EXPECT_FALSE(r.engaged(kCalibCy));
  EXPECT_EQ(r.applied()[kCalibCy], 0.0);
  EXPECT_FALSE(r.engaged(kCalibRadial));
  // One window alone leaves cx at sigma 2.7 px and the focal scale at 0.019 (the correlation);
  // windows correlated the other way pin both down (memory 0.95: about 20 windows' worth).
  const CalibVector sigma = r.sigma();
  EXPECT_GT(sigma[kCalibCx], 0.0);
  EXPECT_LT(sigma[kCalibCx], 0.5);
  EXPECT_LT(sigma[kCalibFocal], 0.003);

  // A curvature that is not positive definite in the refined parameters is ignored.
  CalibMatrix bad = CalibMatrix::Identity();
  bad(1, 2) = bad(2, 1) = 5.0;
  const int before = r.windows();
  r.addWindowStep(CalibVector::Constant(0.1), bad);
  EXPECT_EQ(r.windows(), before);
}

}  // namespace
}  // namespace ldsm
