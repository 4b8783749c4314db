// Whether a keyframe leaving the window is redundant: an earlier visit's map keyframe near it,
// looking the same way, sees nearly all of its points.
#include "reuse/redundancy.h"

#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <utility>

#include "reuse_scene.h"

namespace ldsm {
namespace {

using test::cameraAt;

/// The keyframe leaving the window (id 60, at the origin) and a map to check it against.
struct Leaving {
  std::mt19937_64 rng{5};
  MarginalizedKeyframe kf = test::mapKeyframe(60, cameraAt({0, 0, 0}), rng, 0);
  KeyframeRecord pose{60, 600, 60.0, cameraAt({0, 0, 0})};
  MapStore map;
  ReuseConfig config;

  /// A map keyframe left the window when keyframe `left_at` was the newest.
  void addMapKeyframe(int id, const SE3d& T_w_c, int left_at) {
    map.setKeyframe({id, 10 * id, 1.0 * id, T_w_c});
    MarginalizedKeyframe data = test::mapKeyframe(id, T_w_c, rng, 10);
    data.newest_when_left = left_at;
    map.setKeyframeData(std::make_shared<MarginalizedKeyframe>(std::move(data)));
  }
  RedundancyCheck check() const {
    return checkRedundancy(kf, pose, map, test::reuseCamera(), config);
  }
  /// The share of the keyframe's points a camera at T_w_c sees (computed independently).
  double seenFrom(const SE3d& T_w_c) const {
    return static_cast<double>(test::pointsSeen(kf, pose.T_w_c, pose.scale, T_w_c.inverse())) /
           static_cast<double>(kf.points.size());
  }
};

TEST(Redundancy, AKeyframeAnEarlierVisitAlreadySeesIsRedundant) {
  Leaving l;
  const SE3d T = cameraAt({0.1, -0.05, 0.1}, 3.0);
  l.addMapKeyframe(5, T, 12);
  const RedundancyCheck r = l.check();
  EXPECT_TRUE(r.redundant);
  EXPECT_EQ(r.covered_by, 5);
  EXPECT_NEAR(r.coverage, l.seenFrom(T), 0.005);
  EXPECT_GT(r.coverage, 0.9);
}

TEST(Redundancy, ANovelKeyframeIsNotRedundant) {
  Leaving l;
  l.addMapKeyframe(5, cameraAt({20, 0, 0}), 12);          // elsewhere
  l.addMapKeyframe(6, cameraAt({0.2, 0, 0}, 120.0), 13);  // here, but looking elsewhere
  const RedundancyCheck r = l.check();
  EXPECT_FALSE(r.redundant);
  EXPECT_EQ(r.covered_by, -1);
  EXPECT_EQ(r.coverage, 0.0);
}

TEST(Redundancy, PartialCoverageIsNotEnough) {
  Leaving l;
  const SE3d T = cameraAt({1.15, 0, 0});  // within redundancy_distance x 4 m, a quarter aside
  const double expected = l.seenFrom(T);
  ASSERT_GT(expected, 0.5);
  ASSERT_LT(expected, 0.8);
  l.addMapKeyframe(5, T, 12);
  const RedundancyCheck r = l.check();
  EXPECT_FALSE(r.redundant);
  EXPECT_EQ(r.covered_by, 5);
  EXPECT_NEAR(r.coverage, expected, 0.005);
  l.config.redundancy_coverage = 0.5;
  EXPECT_TRUE(l.check().redundant);
}

TEST(Redundancy, OnlyMapKeyframesWithinTheRedundancyDistanceCount) {
  Leaving l;
  l.addMapKeyframe(5, cameraAt({0, 0, -2.0}), 12);  // 2 m behind: sees all, but not nearby
  EXPECT_FALSE(l.check().redundant);
  EXPECT_EQ(l.check().covered_by, -1);
  l.config.redundancy_distance = 0.6;  // x median depth 4 m = 2.4 m
  const RedundancyCheck r = l.check();
  EXPECT_TRUE(r.redundant);
  EXPECT_EQ(r.covered_by, 5);
  EXPECT_NEAR(r.coverage, 1.0, 1e-9);
}

TEST(Redundancy, OnlyMapKeyframesLookingTheSameWayCount) {
  Leaving l;
  const SE3d T = cameraAt({0, 0, 0}, 8.0);
  l.addMapKeyframe(5, T, 12);
  const RedundancyCheck r = l.check();
  EXPECT_TRUE(r.redundant);
  EXPECT_NEAR(r.coverage, l.seenFrom(T), 0.005);
  l.config.redundancy_angle_deg = 5.0;
  EXPECT_FALSE(l.check().redundant);
  EXPECT_EQ(l.check().covered_by, -1);
}

TEST(Redundancy, OnlyAnEarlierVisitCoversNotTheOdometrysRecentPastNorItself) {
  Leaving l;
  l.addMapKeyframe(55, cameraAt({0.1, 0, 0}), 58);  // left 2 keyframes before 60: its neighbour
  l.addMapKeyframe(60, cameraAt({0, 0, 0}), 12);    // the keyframe's own earlier record
  const RedundancyCheck r = l.check();
  EXPECT_FALSE(r.redundant);
  EXPECT_EQ(r.covered_by, -1);
  l.addMapKeyframe(7, cameraAt({0.1, 0, 0}), 50);  // 60 - min_keyframe_age: old enough
  EXPECT_EQ(l.check().covered_by, 7);
  EXPECT_TRUE(l.check().redundant);
}

TEST(Redundancy, TheMapKeyframeThatSeesMostCoversIt) {
  const SE3d aside = cameraAt({0.6, 0, 0}), close = cameraAt({0.05, 0, 0.05});
  for (const bool close_first : {true, false}) {  // whichever order the map lists them in
    Leaving l;
    l.addMapKeyframe(3, close_first ? close : aside, 10);
    l.addMapKeyframe(4, close_first ? aside : close, 11);
    ASSERT_GT(l.seenFrom(close), l.seenFrom(aside) + 0.05);
    const RedundancyCheck r = l.check();
    EXPECT_TRUE(r.redundant);
    EXPECT_EQ(r.covered_by, close_first ? 3 : 4);
    EXPECT_NEAR(r.coverage, l.seenFrom(close), 0.005);
  }
}

TEST(Redundancy, PointsAreScaledByThePoseRecord) {
  // Inverse depths in units half the map's (a loop correction scaled the keyframe by 2).
  Leaving l;
  for (PatchPoint& p : l.kf.points) p.idepth *= 2.f;
  l.pose.scale = 2.0;
  // The median depth, 4 m with the scale, sets the search radius: 0.3 x 4 m reaches 1 m back.
  l.addMapKeyframe(5, cameraAt({0, 0, -1.0}), 12);
  EXPECT_TRUE(l.check().redundant);
  EXPECT_EQ(l.check().covered_by, 5);
  l.pose.scale = 1.0;  // median depth 2 m: 1 m is beyond the radius
  EXPECT_EQ(l.check().covered_by, -1);
  // The points are where the scale puts them: 0.9 m aside, more of them stay in view at 4 m
  // than at 2 m.
  Leaving m;
  for (PatchPoint& p : m.kf.points) p.idepth *= 2.f;
  m.pose.scale = 2.0;
  const SE3d T = cameraAt({0.9, 0, 0});
  m.addMapKeyframe(5, T, 12);
  const double seen = m.seenFrom(T);
  const RedundancyCheck r = m.check();
  EXPECT_EQ(r.covered_by, 5);
  EXPECT_NEAR(r.coverage, seen, 0.005);
  m.pose.scale = 1.0;
  ASSERT_LT(m.seenFrom(T), seen - 0.05);
}

TEST(Redundancy, AKeyframeWithoutPointsWithDepthIsNeverRedundant) {
  Leaving l;
  l.addMapKeyframe(5, cameraAt({0, 0, 0}), 12);
  ASSERT_TRUE(l.check().redundant);
  // Points without a depth do not count, neither as seen nor as unseen.
  for (std::size_t i = 0; i < l.kf.points.size(); i += 2) l.kf.points[i].idepth = 0.f;
  EXPECT_TRUE(l.check().redundant);
  EXPECT_NEAR(l.check().coverage, 1.0, 1e-9);
  for (PatchPoint& p : l.kf.points) p.idepth = 0.f;
  EXPECT_FALSE(l.check().redundant);
  l.kf.points.clear();
  const RedundancyCheck r = l.check();
  EXPECT_FALSE(r.redundant);
  EXPECT_EQ(r.covered_by, -1);
}

}  // namespace
}  // namespace ldsm
