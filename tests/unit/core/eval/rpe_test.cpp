#include "ldsm/eval/rpe.h"

#include <gtest/gtest.h>

#include "ldsm/error.h"
#include "synthetic_trajectory.h"

namespace ldsm::eval {
namespace {

// Straight drive along x at 0.1 m per pose while the camera sways: chord == arc, so a scale
// error shows up exactly as a relative translation error.
Trajectory straightDrive(std::size_t n) {
  Trajectory t;
  for (std::size_t i = 0; i < n; ++i) {
    StampedPose sp;
    sp.timestamp = 0.1 * static_cast<double>(i);
    sp.pose.translation = Eigen::Vector3d(0.1 * static_cast<double>(i), 0.0, 0.0);
    sp.pose.rotation = Eigen::AngleAxisd(0.3 * std::sin(0.05 * i), Eigen::Vector3d::UnitY()) *
                       Eigen::AngleAxisd(0.2 * std::cos(0.03 * i), Eigen::Vector3d::UnitX());
    t.push_back(sp);
  }
  return t;
}

TEST(Rpe, DefaultLengths) {
  const auto kitti = defaultRpeLengths(3000.0);
  ASSERT_EQ(kitti.size(), 8u);
  EXPECT_DOUBLE_EQ(kitti.front(), 100.0);
  EXPECT_DOUBLE_EQ(kitti.back(), 800.0);
  const auto shortp = defaultRpeLengths(10.0);
  ASSERT_EQ(shortp.size(), 8u);
  EXPECT_DOUBLE_EQ(shortp.front(), 1.0);
  EXPECT_DOUBLE_EQ(shortp.back(), 8.0);
  EXPECT_TRUE(defaultRpeLengths(0.0).empty());
}

TEST(Rpe, PerfectEstimateHasNoError) {
  const Trajectory gt = testing::curvedTrajectory(400);
  // A global rigid motion does not change relative motions.
  const Trajectory est =
      testing::transformed(gt, testing::makeSim3(0.8, {1, 1, 0}, {5, 5, 5}, 1.0));
  const RpeResult r = computeRpe(gt, est);
  ASSERT_TRUE(r.valid());
  EXPECT_LT(r.translation_percent, 1e-9);
  EXPECT_LT(r.rotation_deg_per_m, 1e-9);
}

TEST(Rpe, OnePercentScaleErrorGivesOnePercent) {
  const Trajectory gt = straightDrive(500);  // 49.9 m
  const Trajectory est =
      testing::transformed(gt, testing::makeSim3(0.0, {0, 0, 1}, {0, 0, 0}, 1.01));
  RpeOptions o;
  o.lengths = {5.0, 10.0, 20.0};
  const RpeResult r = computeRpe(gt, est, o);
  ASSERT_TRUE(r.valid());
  // A segment ends at the first pose at least L further on: it may overshoot by one 0.1 m step.
  EXPECT_NEAR(r.translation_percent, 1.0, 0.01 * 0.1 / 5.0 * 100.0);
  EXPECT_LT(r.rotation_deg_per_m, 1e-9);
  ASSERT_EQ(r.per_length.size(), 3u);
  EXPECT_EQ(r.per_length[0].segments, 450u);  // starts 0..449 have 5 m left
  EXPECT_NEAR(r.per_length[2].translation_percent, 1.0, 0.01 * 0.1 / 20.0 * 100.0);

  // Undoing the scale removes the error; the step thins the segments.
  o.scale = 1.0 / 1.01;
  o.step = 10;
  const RpeResult fixed = computeRpe(gt, est, o);
  EXPECT_LT(fixed.translation_percent, 1e-9);
  EXPECT_EQ(fixed.per_length[0].segments, 45u);
}

TEST(Rpe, HeadingDriftGivesKnownRotationRate) {
  // Ground truth keeps a constant (tilted) orientation; the estimate turns about its own z axis
  // at `rate` rad per metre travelled, so over a segment of d metres the relative rotations
  // differ by exactly rate * d.
  Trajectory gt = straightDrive(500);
  const Eigen::Quaterniond tilt(Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 1, 0).normalized()));
  for (auto& sp : gt) sp.pose.rotation = tilt;
  Trajectory est = gt;
  const double rate = 0.02;
  for (std::size_t i = 0; i < est.size(); ++i) {
    const double s = 0.1 * static_cast<double>(i);
    est[i].pose.rotation = tilt * Eigen::AngleAxisd(rate * s, Eigen::Vector3d::UnitZ());
  }
  RpeOptions o;
  o.lengths = {10.0};
  const RpeResult r = computeRpe(gt, est, o);
  const double expected = rate * 180.0 / EIGEN_PI;
  EXPECT_NEAR(r.rotation_deg_per_m, expected, expected * 0.1 / 10.0);  // <= one step overshoot
}

TEST(Rpe, TooShortPathIsInvalid) {
  const Trajectory gt = straightDrive(20);
  RpeOptions o;
  o.lengths = {100.0};
  const RpeResult r = computeRpe(gt, gt, o);
  EXPECT_FALSE(r.valid());
  ASSERT_EQ(r.per_length.size(), 1u);
  EXPECT_EQ(r.per_length[0].segments, 0u);
}

TEST(Rpe, BadOptionsAreConfigErrors) {
  const Trajectory gt = straightDrive(20);
  RpeOptions o;
  o.lengths = {-1.0};
  EXPECT_THROW(computeRpe(gt, gt, o), ConfigError);
  o.lengths = {1.0};
  o.step = 0;
  EXPECT_THROW(computeRpe(gt, gt, o), ConfigError);
  o.step = 1;
  o.scale = 0.0;
  EXPECT_THROW(computeRpe(gt, gt, o), ConfigError);
}

}  // namespace
}  // namespace ldsm::eval
