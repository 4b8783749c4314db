// Where the newest keyframe is in the map when several map keyframes say so: the distance of two
// poses measured on the scene they see, the largest group of map keyframes that agree, and a frame
// carried from the window into the map.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <vector>

#include "camera/pyramid_camera.h"
#include "math/se3.h"
#include "reuse/drift_consensus.h"

namespace ldsm {
namespace {

LevelCamera testCamera() {
  PinholeIntrinsics k;
  k.fx = k.fy = 400.0;
  k.cx = 319.5;
  k.cy = 239.5;
  k.width = 640;
  k.height = 480;
  return PyramidCamera(k, 1)[0];
}

/// A scene 2 m in front of the identity camera, spread over the image.
std::vector<Eigen::Vector3d> testScene() {
  std::vector<Eigen::Vector3d> s;
  for (int i = -3; i <= 3; ++i)
    for (int j = -2; j <= 2; ++j) s.emplace_back(0.25 * i, 0.25 * j, 2.0 + 0.1 * ((i + j) % 3));
  return s;
}

SE3d moved(double tx, double ty, double tz, double rx = 0, double ry = 0, double rz = 0) {
  SE3d::Tangent x;
  x << tx, ty, tz, rx, ry, rz;
  return SE3d::exp(x);
}

TEST(PoseDistancePx, IsTheMeanShiftOfTheSceneInTheImage) {
  const LevelCamera cam = testCamera();
  const std::vector<Eigen::Vector3d> scene = testScene();
  EXPECT_NEAR(poseDistancePx(SE3d(), SE3d(), cam, scene), 0.0, 1e-9);
  // A sideways step of 1 cm shifts every point by fx * 0.01 / z pixels.
  double expected = 0.0;
  for (const Eigen::Vector3d& X : scene) expected += 400.0 * 0.01 / X.z();
  expected /= static_cast<double>(scene.size());
  EXPECT_NEAR(poseDistancePx(SE3d(), moved(0.01, 0, 0), cam, scene), expected, 1e-3);
  // Symmetric.
  EXPECT_NEAR(poseDistancePx(moved(0.01, 0, 0), SE3d(), cam, scene), expected, 1e-3);
}

TEST(PoseDistancePx, ARotationTradedForATranslationCostsLittleOnTheScene) {
  // A small yaw and the sideways step that moves the scene's centre back: the two poses differ by
  // centimetres and a degree, yet put the scene within a pixel of each other.
  const LevelCamera cam = testCamera();
  const std::vector<Eigen::Vector3d> scene = testScene();
  const double yaw = 0.01;
  const SE3d traded = moved(-2.0 * yaw, 0, 0, 0, yaw, 0);
  EXPECT_LT(poseDistancePx(SE3d(), traded, cam, scene), 1.0);
  EXPECT_GT(poseDistancePx(SE3d(), moved(0, 0, 0, 0, yaw, 0), cam, scene), 3.0);
}

TEST(PoseDistancePx, NothingInFrontOfBothIsInfinitelyFar) {
  const LevelCamera cam = testCamera();
  const std::vector<Eigen::Vector3d> behind = {{0, 0, -1}};
  EXPECT_TRUE(std::isinf(poseDistancePx(SE3d(), SE3d(), cam, behind)));
  EXPECT_TRUE(std::isinf(poseDistancePx(SE3d(), SE3d(), cam, {})));
}

TEST(DriftConsensus, TheLargestAgreeingGroupWinsOverAnOutlier) {
  const LevelCamera cam = testCamera();
  const std::vector<Eigen::Vector3d> scene = testScene();
  std::vector<DriftCandidate> c = {
      {3, moved(0.020, 0, 0), 100},    // agree (within 0.1 px)
      {5, moved(0.0202, 0, 0), 120},   //
      {9, moved(-0.030, 0, 0), 500},   // alone, though with the most points in view
      {11, moved(0.0199, 0, 0), 80}};  //
  const DriftConsensus d = findDriftConsensus(c, cam, scene, 1.0, 2);
  ASSERT_TRUE(d.found);
  EXPECT_EQ(d.agreeing.size(), 3u);
  EXPECT_EQ(d.id, 5);  // the group's member with the most points in view
  EXPECT_TRUE(d.T_c_w.translation().isApprox(c[1].T_c_w.translation()));
  EXPECT_LT(d.spread_px, 1.0);
  EXPECT_GT(d.spread_px, 0.0);
}

TEST(DriftConsensus, NotFoundWithTooFewInAgreement) {
  const LevelCamera cam = testCamera();
  const std::vector<Eigen::Vector3d> scene = testScene();
  // Every pair 2 cm apart: 4 px, beyond 1 px agreement.
  const std::vector<DriftCandidate> c = {
      {1, moved(0.00, 0, 0), 10}, {2, moved(0.02, 0, 0), 10}, {3, moved(0.04, 0, 0), 10}};
  EXPECT_FALSE(findDriftConsensus(c, cam, scene, 1.0, 2).found);
  // A lone candidate is its own group of one.
  const DriftConsensus one = findDriftConsensus(c, cam, scene, 1.0, 1);
  EXPECT_TRUE(one.found);
  EXPECT_EQ(one.agreeing.size(), 1u);
  EXPECT_FALSE(findDriftConsensus({}, cam, scene, 1.0, 1).found);
  EXPECT_FALSE(findDriftConsensus(c, cam, scene, 1.0, 0).found);  // 0: switched off
}

TEST(DriftConsensus, TiesGoToMorePointsInViewThenTheLowerId) {
  const LevelCamera cam = testCamera();
  const std::vector<Eigen::Vector3d> scene = testScene();
  // Two groups of two, far apart; the second has the candidate with most points in view.
  std::vector<DriftCandidate> c = {{4, moved(0.00, 0, 0), 50},
                                   {6, moved(0.0001, 0, 0), 50},
                                   {8, moved(0.05, 0, 0), 60},
                                   {2, moved(0.0501, 0, 0), 40}};
  DriftConsensus d = findDriftConsensus(c, cam, scene, 1.0, 2);
  ASSERT_TRUE(d.found);
  EXPECT_EQ(d.id, 8);
  // Equal evidence: the lower id, whatever the order given.
  for (DriftCandidate& x : c) x.in_view = 50;
  d = findDriftConsensus(c, cam, scene, 1.0, 2);
  EXPECT_EQ(d.id, 2);
  std::reverse(c.begin(), c.end());
  EXPECT_EQ(findDriftConsensus(c, cam, scene, 1.0, 2).id, 2);
}

TEST(CarriedIntoMap, KeepsTheFramesPoseRelativeToTheNewestKeyframe) {
  const SE3d newest_window = moved(0.3, -0.1, 0.2, 0.05, -0.02, 0.1);
  const SE3d newest_map = moved(0.32, -0.09, 0.18, 0.06, -0.03, 0.1);
  const SE3d frame = moved(0.01, 0.02, 0.05, 0.0, 0.01, 0.0) * newest_window;
  const SE3d carried = carriedIntoMap(frame, newest_window, newest_map);
  const SE3d rel_window = frame * newest_window.inverse();
  const SE3d rel_map = carried * newest_map.inverse();
  EXPECT_LT((rel_window.translation() - rel_map.translation()).norm(), 1e-12);
  EXPECT_LT((rel_window.so3().matrix() - rel_map.so3().matrix()).norm(), 1e-12);
  // The newest keyframe itself goes to its map pose; with no drift nothing moves.
  EXPECT_LT((carriedIntoMap(newest_window, newest_window, newest_map).translation() -
             newest_map.translation())
                .norm(),
            1e-12);
  EXPECT_LT(
      (carriedIntoMap(frame, newest_window, newest_window).translation() - frame.translation())
          .norm(),
      1e-12);
}

}  // namespace
}  // namespace ldsm
