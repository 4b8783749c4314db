#include "ldsm/eval/ate.h"

#include <gtest/gtest.h>

#include <random>

#include "ldsm/error.h"
#include "synthetic_trajectory.h"

namespace ldsm::eval {
namespace {

using testing::curvedTrajectory;
using testing::makeSim3;
using testing::transformed;

TEST(Ate, ZeroUnderKnownSim3AndScaleRecovered) {
  const Trajectory gt = curvedTrajectory(300);
  // est -> gt is `g`: build the estimate with its inverse.
  const Alignment g = makeSim3(1.3, {1.0, 2.0, -0.5}, {3.0, -7.0, 2.0}, 2.7);
  const Trajectory est = transformed(gt, g.inverse());
  const AteResult r = computeAte(gt, est, AlignMode::Sim3);
  EXPECT_LT(r.rmse, 1e-9);
  EXPECT_LT(r.max, 1e-9);
  EXPECT_EQ(r.matched, 300u);
  EXPECT_NEAR(r.alignment.scale, 2.7, 1e-9);
  EXPECT_NEAR(r.sim3_scale, 2.7, 1e-9);
  EXPECT_LT((r.alignment.rotation - g.rotation).norm(), 1e-9);
  EXPECT_LT(r.rotation_rmse_deg, 1e-6);
  ASSERT_EQ(r.aligned_estimate.size(), est.size());
  for (std::size_t i = 0; i < gt.size(); ++i) {
    EXPECT_LT((r.aligned_estimate[i].pose.translation - gt[i].pose.translation).norm(), 1e-9);
  }
  // Path length of the matched ground truth, by an independent sum.
  double length = 0.0;
  for (std::size_t i = 1; i < gt.size(); ++i) {
    length += (gt[i].pose.translation - gt[i - 1].pose.translation).norm();
  }
  EXPECT_NEAR(r.gt_path_length, length, 1e-9);
}

TEST(Ate, Se3ModeReportsTheScaleError) {
  const Trajectory gt = curvedTrajectory(300);
  const Alignment scale_up = makeSim3(0.0, {0, 0, 1}, {0, 0, 0}, 1.25);
  const Trajectory est = transformed(gt, scale_up);

  const AteResult se3 = computeAte(gt, est, AlignMode::SE3);
  EXPECT_EQ(se3.alignment.scale, 1.0);
  EXPECT_GT(se3.rmse, 0.05);               // a wrong scale is an error in SE(3) mode
  EXPECT_NEAR(se3.sim3_scale, 0.8, 1e-9);  // est is 1.25x too large -> scale 1/1.25

  const AteResult sim3 = computeAte(gt, est, AlignMode::Sim3);
  EXPECT_LT(sim3.rmse, 1e-9);
  EXPECT_NEAR(sim3.alignment.scale, 0.8, 1e-9);
}

// A second estimate in the frame of a first (a session started in a saved map) is measured under
// the first one's alignment, unchanged: an offset its own alignment would hide counts in full.
TEST(Ate, UnderAGivenAlignmentAnOffsetCountsInFull) {
  const Trajectory gt = curvedTrajectory(300);
  const Alignment g = makeSim3(0.7, {0.0, 1.0, 0.5}, {2.0, -1.0, 4.0}, 0.4);
  const Trajectory est = transformed(gt, g.inverse());
  const AteResult exact = computeAteUnder(gt, est, g);
  EXPECT_LT(exact.rmse, 1e-9);
  EXPECT_EQ(exact.matched, 300u);
  EXPECT_EQ(exact.sim3_scale, 0.4);
  EXPECT_LT(exact.rotation_rmse_deg, 1e-6);

  // The same estimate 5 cm off in its own frame (units of est): 0.4 * 0.05 = 2 cm in gt units,
  // at every pose, while its own alignment takes the offset away.
  Trajectory shifted = est;
  for (StampedPose& sp : shifted) sp.pose.translation += Eigen::Vector3d(0.0, 0.05, 0.0);
  const AteResult under = computeAteUnder(gt, shifted, g);
  EXPECT_NEAR(under.rmse, 0.02, 1e-9);
  EXPECT_NEAR(under.max, 0.02, 1e-9);
  EXPECT_NEAR(under.median, 0.02, 1e-9);
  EXPECT_LT(computeAte(gt, shifted).rmse, 1e-9);
  ASSERT_EQ(under.aligned_estimate.size(), shifted.size());
  EXPECT_NEAR((under.aligned_estimate[7].pose.translation - gt[7].pose.translation).norm(), 0.02,
              1e-9);

  // A part of the trajectory only: the matched poses are those of the part.
  const Trajectory second_half(shifted.begin() + 150, shifted.end());
  const AteResult half = computeAteUnder(gt, second_half, g);
  EXPECT_EQ(half.matched, 150u);
  EXPECT_NEAR(half.rmse, 0.02, 1e-9);

  Trajectory late = est;
  for (StampedPose& sp : late) sp.timestamp += 1000.0;
  EXPECT_THROW(computeAteUnder(gt, late, g), InputError);
}

TEST(Ate, GaussianNoiseGivesSigmaSqrt3) {
  const std::size_t n = 4000;
  const double sigma = 0.05;
  const Trajectory gt = curvedTrajectory(n, 0.05);
  Trajectory est = transformed(gt, makeSim3(-0.6, {0.2, 1.0, 0.1}, {1.0, 1.0, 1.0}, 0.5));
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, sigma * 0.5);  // est is at half scale
  for (auto& sp : est) sp.pose.translation += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));

  const AteResult r = computeAte(gt, est, AlignMode::Sim3);
  // E[||e||^2] = 3 sigma^2; the rmse estimate has a relative spread of ~0.7 % for n = 4000.
  EXPECT_NEAR(r.rmse, sigma * std::sqrt(3.0), 0.04 * sigma * std::sqrt(3.0));
  // Mean of a Maxwell distribution: 2 sigma sqrt(2 / pi).
  EXPECT_NEAR(r.mean, 2.0 * sigma * std::sqrt(2.0 / EIGEN_PI), 0.04 * sigma);
  EXPECT_NEAR(r.alignment.scale, 2.0, 0.01);
  EXPECT_LE(r.median, r.max);
}

TEST(Ate, MatchesOnlyPosesWithinTolerance) {
  const Trajectory gt = curvedTrajectory(100);
  Trajectory est = curvedTrajectory(100, 0.1, 0.003);  // 3 ms late
  EXPECT_EQ(computeAte(gt, est, AlignMode::Sim3, 0.005).matched, 100u);
  EXPECT_THROW(computeAte(gt, est, AlignMode::Sim3, 0.001), InputError);  // nothing matches
}

TEST(Ate, StraightLineIsDegenerate) {
  Trajectory gt;
  for (int i = 0; i < 20; ++i) {
    StampedPose sp;
    sp.timestamp = i;
    sp.pose.translation = Eigen::Vector3d(i, 2.0 * i, 0.0);
    gt.push_back(sp);
  }
  EXPECT_THROW(computeAte(gt, gt), InputError);
}

}  // namespace
}  // namespace ldsm::eval
