// Which map keyframes the reactivation search brings back: the geometric check (looking the same
// way, enough of its points in view), the feature check (ORB matches where its corners project),
// the revisit rule, and where candidates come from (covisibility and the spatial neighbourhood).
#include "reuse/reactivation_search.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "map/map_store.h"
#include "reuse_scene.h"

namespace ldsm {
namespace {

using test::cameraAt;

/// A map keyframe at the origin (id 5) and the newest keyframe seeing it from `T_w_view`.
struct Revisit {
  std::mt19937_64 rng{42};
  SE3d T_w_kf = cameraAt({0, 0, 0});
  MarginalizedKeyframe kf = test::mapKeyframe(5, T_w_kf, rng);
  KeyframeRecord record{5, 50, 5.0, T_w_kf};
  ReuseView view;

  explicit Revisit(const SE3d& T_w_view, int flips = 6) : view(test::viewAt(T_w_view)) {
    test::addCornersSeen(view, kf, T_w_kf, view.T_c_w, rng, flips, 40);
  }
  ReuseCheck check(const ReuseConfig& config = {}) const {
    return ReactivationSearch(config).check(view, kf, record);
  }
};

TEST(ReactivationSearch, AcceptsAKeyframeThatSeesTheViewAndMatchesItsCorners) {
  Revisit r(cameraAt({0.3, -0.1, 0.2}, 5.0));
  const ReuseCheck c = r.check();
  EXPECT_TRUE(c.accepted) << c.reason;
  EXPECT_TRUE(c.reason.empty());
  EXPECT_EQ(c.id, 5);
  const int seen = test::pointsSeen(r.kf, r.T_w_kf, 1.0, r.view.T_c_w);
  EXPECT_NEAR(c.in_view, seen, 2);
  EXPECT_NEAR(c.overlap, static_cast<double>(seen) / static_cast<double>(r.kf.points.size()), 0.01);
  EXPECT_GT(c.overlap, 0.7);
  // Nearly every corner in view is matched where it projects (40 unrelated corners add none).
  const int corners_seen = static_cast<int>(r.view.corners.size()) - 40;
  EXPECT_GE(c.matches, corners_seen * 9 / 10);
  EXPECT_LE(c.matches, corners_seen);
}

TEST(ReactivationSearch, GeometricCheckRejectsAKeyframeLookingAway) {
  Revisit r(cameraAt({0, 0, 0}, 70.0));  // 70 degrees > max_view_angle_deg (60)
  const ReuseCheck c = r.check();
  EXPECT_FALSE(c.accepted);
  EXPECT_NE(c.reason.find("viewing angle"), std::string::npos) << c.reason;
  EXPECT_EQ(c.matches, 0);
}

TEST(ReactivationSearch, GeometricCheckRejectsAKeyframeWhosePointsAreBehindTheCamera) {
  // Same direction, but beyond the surface (3.5 .. 4.5 m): every point is behind the camera.
  Revisit r(cameraAt({0, 0, 6.0}));
  const ReuseCheck c = r.check();
  EXPECT_FALSE(c.accepted);
  EXPECT_EQ(c.in_view, 0);
  EXPECT_NE(c.reason.find("points in view"), std::string::npos) << c.reason;
}

TEST(ReactivationSearch, GeometricCheckRejectsAKeyframeTooFarAside) {
  Revisit r(cameraAt({8.0, 0, 0}));  // parallel, 8 m to the side: nothing in common
  const ReuseCheck c = r.check();
  EXPECT_FALSE(c.accepted);
  EXPECT_EQ(c.in_view, 0);
  EXPECT_NE(c.reason.find("points in view"), std::string::npos) << c.reason;
}

TEST(ReactivationSearch, GeometricCheckNeedsTheMinimumOverlap) {
  // 3.9 m aside about a fifth of the points stay in view (more than min_points_in_view, fewer than
  // min_overlap); 2 m aside about half do.
  Revisit small(cameraAt({3.9, 0, 0}));
  const ReuseCheck c = small.check();
  EXPECT_FALSE(c.accepted);
  EXPECT_GE(c.in_view, 100);
  EXPECT_GT(c.overlap, 0.1);
  EXPECT_LT(c.overlap, 0.3);
  EXPECT_EQ(c.matches, 0) << "the feature check must not run after a geometric rejection";
  Revisit half(cameraAt({2.0, 0, 0}));
  const ReuseCheck h = half.check();
  EXPECT_TRUE(h.accepted) << h.reason;
  EXPECT_GT(h.overlap, 0.4);
  EXPECT_LT(h.overlap, 0.7);
}

TEST(ReactivationSearch, FeatureCheckRejectsRightGeometryWithUnrelatedDescriptors) {
  Revisit r(cameraAt({0.3, 0, 0}));
  std::mt19937_64 other(7);
  for (OrbDescriptor& d : r.view.descriptors) d = test::randomDescriptor(other);
  const ReuseCheck c = r.check();
  EXPECT_FALSE(c.accepted);
  EXPECT_GT(c.overlap, 0.8);  // it passed the geometric check
  EXPECT_LT(c.matches, 5);
  EXPECT_NE(c.reason.find("consistent ORB matches"), std::string::npos) << c.reason;
}

TEST(ReactivationSearch, FeatureCheckRejectsMatchesAwayFromTheProjection) {
  // The descriptors match, but the view's pose is 0.5 m off (a drifted estimate): the matched
  // corners lie ~30 px from where the keyframe's corners project.
  Revisit r(cameraAt({0.3, 0, 0}));
  const ReuseCheck right = r.check();
  ASSERT_TRUE(right.accepted) << right.reason;
  r.view.T_c_w = cameraAt({0.8, 0, 0}).inverse();
  const ReuseCheck c = r.check();
  EXPECT_FALSE(c.accepted);
  EXPECT_GT(c.overlap, 0.5);
  EXPECT_LT(c.matches, 5);
  EXPECT_NE(c.reason.find("ORB"), std::string::npos) << c.reason;
}

TEST(ReactivationSearch, FeatureRadiusBoundsTheConsistentMatches) {
  Revisit r(cameraAt({0.3, 0, 0}));
  // Shift the view's corners by 5 px: within the default 8 px, outside 3 px.
  for (Eigen::Vector2f& c : r.view.corners) c.x() += 5.f;
  ReuseConfig tight;
  tight.feature_radius_px = 3.0;
  EXPECT_TRUE(r.check().accepted);
  const ReuseCheck c = r.check(tight);
  EXPECT_FALSE(c.accepted);
  EXPECT_EQ(c.matches, 0);
}

TEST(ReactivationSearch, UsesThePoseRecordAndItsScaleNotTheKeyframesOwnPose) {
  // A keyframe whose map was scaled by 2 after a loop correction: its inverse depths are in its
  // old units (depths halved) and its own T_w_c is stale; only the record places it right.
  std::mt19937_64 rng(3);
  const SE3d T_w_kf = cameraAt({0, 0, 0});
  MarginalizedKeyframe kf = test::mapKeyframe(5, cameraAt({1, 0, 0}, 20.0), rng, 120, 8, 2.0);
  const KeyframeRecord record{5, 50, 5.0, T_w_kf, 2.0};
  ReuseView view = test::viewAt(cameraAt({1.0, 0, 0}));
  MarginalizedKeyframe truth = kf;
  for (float& d : truth.corner_idepth) d /= 2.f;
  test::addCornersSeen(view, truth, T_w_kf, view.T_c_w, rng);
  const ReactivationSearch search{ReuseConfig{}};
  const ReuseCheck c = search.check(view, kf, record);
  EXPECT_TRUE(c.accepted) << c.reason;
  EXPECT_GE(c.matches, 50);
  KeyframeRecord unscaled = record;
  unscaled.scale = 1.0;  // depths half the truth: 1 m aside, the projections miss by ~65 px
  EXPECT_FALSE(search.check(view, kf, unscaled).accepted);
}

TEST(ReactivationSearch, RejectsTheOdometrysRecentPast) {
  Revisit r(cameraAt({0.3, 0, 0}));
  r.kf.newest_when_left = r.view.keyframe_id - 4;  // left 4 < min_keyframe_age (10) ago
  const ReuseCheck c = r.check();
  EXPECT_FALSE(c.accepted);
  EXPECT_NE(c.reason.find("left the window 4 keyframes ago"), std::string::npos) << c.reason;
}

TEST(ReactivationSearch, NeedsARevisitALongWayRoundOrTheSamePlace) {
  // 1 m from the keyframe (more than same_place_distance x median depth = 0.4 m).
  Revisit r(cameraAt({1.0, 0, 0}));
  r.view.path_length = r.kf.path_length + 2.0;  // < revisit_ratio (3) x 1 m: straight on
  const ReuseCheck c = r.check();
  EXPECT_FALSE(c.accepted);
  EXPECT_NE(c.reason.find("not a revisit"), std::string::npos) << c.reason;
  r.view.path_length = r.kf.path_length + 3.5;  // came back a long way round
  EXPECT_TRUE(r.check().accepted);
  Revisit same(cameraAt({0.3, 0, 0}));
  same.view.path_length = same.kf.path_length;  // no travel, but practically the same place
  EXPECT_TRUE(same.check().accepted);
}

/// A map whose window is keyframes 57..60 (poses only), the camera at the origin.
struct CandidateMap {
  MapStore map;
  std::mt19937_64 rng{1};
  CandidateMap() {
    for (int id = 57; id <= 60; ++id) map.setKeyframe({id, 10 * id, 1.0 * id, cameraAt({0, 0, 0})});
  }
  void add(int id, const Eigen::Vector3d& centre) {
    map.setKeyframe({id, 10 * id, 1.0 * id, cameraAt(centre)});
    map.setKeyframeData(
        std::make_shared<MarginalizedKeyframe>(test::mapKeyframe(id, cameraAt(centre), rng, 10)));
  }
};

TEST(ReactivationSearch, CandidatesComeFromCovisibilityAndTheSpatialNeighbourhoodOnly) {
  CandidateMap m;
  m.add(10, {50, 0, 0});   // far away, covisible with the window (1 hop)
  m.add(11, {60, 0, 0});   // 2 hops
  m.add(12, {70, 0, 0});   // 3 hops: beyond search_hops
  m.add(20, {0.5, 0, 0});  // near the camera (within search_radius x median depth = 4 m)
  m.add(21, {1.0, 0, 0});  // near, but excluded (already in the window)
  m.add(30, {-20, 0, 0});  // neither
  m.map.connect(60, 10);
  m.map.connect(10, 11);
  m.map.connect(11, 12);
  ReuseConfig config;
  config.search_hops = 2;
  const ReuseView view = test::viewAt(cameraAt({0, 0, 0}));
  EXPECT_EQ(ReactivationSearch(config).candidates(view, m.map, {21}),
            (std::vector<int>{10, 11, 20}));
  config.search_hops = 3;
  EXPECT_EQ(ReactivationSearch(config).candidates(view, m.map, {21}),
            (std::vector<int>{10, 11, 12, 20}));
}

TEST(ReactivationSearch, TooManyCandidatesKeepsTheSpatiallyNearest) {
  CandidateMap m;
  m.add(3, {3.0, 0, 0});
  m.add(4, {0.5, 0, 0});
  m.add(8, {2.0, 0, 0});
  m.add(9, {1.0, 0, 0});
  m.add(10, {50, 0, 0});
  m.map.connect(60, 10);
  ReuseConfig config;
  config.max_candidates = 2;
  const ReuseView view = test::viewAt(cameraAt({0, 0, 0}));
  EXPECT_EQ(ReactivationSearch(config).candidates(view, m.map, {}), (std::vector<int>{4, 9}));
}

TEST(ReactivationSearch, SearchPutsTheAcceptedFirstMostMatchesFirst) {
  std::mt19937_64 rng(11);
  MapStore map;
  const SE3d T_w_c = cameraAt({0, 0, 0});
  const auto add = [&](const MarginalizedKeyframe& kf) {
    map.setKeyframe({kf.id, 10 * kf.id, 1.0 * kf.id, kf.T_w_c});
    map.setKeyframeData(std::make_shared<MarginalizedKeyframe>(kf));
  };
  const MarginalizedKeyframe few = test::mapKeyframe(3, T_w_c, rng, 30);
  const MarginalizedKeyframe many = test::mapKeyframe(7, T_w_c, rng, 120);
  const MarginalizedKeyframe away = test::mapKeyframe(9, cameraAt({0, 0, 0}, 90.0), rng, 120);
  add(few);
  add(many);
  add(away);
  map.setKeyframe({11, 110, 11.0, T_w_c});  // a pose without data (culled): never a candidate
  map.connect(60, 11);
  ReuseView view = test::viewAt(cameraAt({0.2, 0, 0}));
  test::addCornersSeen(view, few, T_w_c, view.T_c_w, rng);
  test::addCornersSeen(view, many, T_w_c, view.T_c_w, rng);
  const std::vector<ReuseCheck> checks = ReactivationSearch(ReuseConfig{}).search(view, map, {});
  ASSERT_EQ(checks.size(), 3u);
  EXPECT_EQ(checks[0].id, 7);
  EXPECT_EQ(checks[1].id, 3);
  EXPECT_EQ(checks[2].id, 9);
  EXPECT_TRUE(checks[0].accepted && checks[1].accepted) << checks[1].reason;
  EXPECT_FALSE(checks[2].accepted);
  EXPECT_GT(checks[0].matches, checks[1].matches);
  EXPECT_GE(checks[1].matches, 20);
}

}  // namespace
}  // namespace ldsm
