// Loop corrections move keyframes that left the window, with their frames and points; keyframes
// folded out of the pose graph move with the keyframe they follow.
#include <gtest/gtest.h>

#include <cfloat>

#include "map/map_store.h"

namespace ldsm {
namespace {

TEST(MapStoreCorrection, KeyframesFramesAndPointsMoveWithTheSim3) {
  MapStore store;
  const SE3d T0(SO3d(), Eigen::Vector3d(0, 0, 0));
  const SE3d T1(SO3d::exp(Eigen::Vector3d(0, 0.1, 0)), Eigen::Vector3d(1, 0, 0));
  store.setKeyframe({0, 0, 0.0, T0});
  store.setKeyframe({1, 10, 1.0, T1});
  store.addFrame({11, 1.1, 1, SE3d(SO3d(), Eigen::Vector3d(0, 0, 0.5))});
  MapPoint p;
  p.position = T1 * Eigen::Vector3d(0, 0, 2);  // 2 m in front of keyframe 1
  MapPoint q;
  q.position = T0 * Eigen::Vector3d(0, 0, 3);  // hosted by keyframe 0, which stays
  MapPoint r;
  r.position = Eigen::Vector3d(5, 5, 5);  // no known host: never moves
  store.addPoints({{p, 1}, {q, 0}, {r, -1}});

  // Keyframe 1 really is 0.2 m further along x and the map around it has scale 2.
  const Sim3d S1_new(T1.so3(), T1.translation() + Eigen::Vector3d(0.2, 0, 0), 2.0);
  EXPECT_EQ(store.applyCorrection({{0, Sim3d(T0)}, {1, S1_new}, {7, Sim3d()}}), 2);

  const Trajectory kfs = store.keyframeTrajectory();
  ASSERT_EQ(kfs.size(), 2u);
  EXPECT_LT((kfs[1].pose.translation - S1_new.translation()).norm(), 1e-12);
  const Trajectory frames = store.frameTrajectory();
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_LT((frames[0].pose.translation - S1_new * Eigen::Vector3d(0, 0, 0.5)).norm(), 1e-12);
  const std::vector<MapPoint> pts = store.points();
  ASSERT_EQ(pts.size(), 3u);
  // Points are stored in float (HostedPoint): the moved point is where the Sim(3) puts it, to
  // within the rounding of its stored and of its moved coordinates.
  const Eigen::Vector3d ideal = S1_new * Eigen::Vector3d(0, 0, 2);
  EXPECT_LT((pts[0].position - ideal).norm(), 4.0 * FLT_EPSILON * ideal.norm());
  // These two are exact in float (0, 0, 3 and 5, 5, 5), so storage keeps them to the bit.
  EXPECT_LT((pts[1].position - q.position).norm(), 1e-12);
  EXPECT_LT((pts[2].position - r.position).norm(), 1e-12);
}

TEST(MapStoreCorrection, FoldedKeyframesMoveWithTheKeyframeTheyFollow) {
  MapStore store;
  // Keyframes 0..4 along x; 2 follows 1, 3 follows 2 (a chain of folds), 4 follows 0.
  for (int i = 0; i < 5; ++i)
    store.setKeyframe({i, 10 * i, 1.0 * i,
                       SE3d(SO3d::exp(Eigen::Vector3d(0, 0.05 * i, 0)), Eigen::Vector3d(i, 0, 0))});
  store.addFrame({31, 3.1, 3, SE3d(SO3d(), Eigen::Vector3d(0, 0, 0.5))});
  store.followKeyframes({{2, 1}, {3, 2}, {4, 0}});
  const KeyframeRecord k1 = store.keyframe(1), k2 = store.keyframe(2), k3 = store.keyframe(3);
  const Sim3d S1(k1.T_w_c), S2(k2.T_w_c), S3(k3.T_w_c);
  // The correction lists the graph's vertices only: 0 stays, 1 moves and scales.
  const Sim3d S1_new(SO3d::exp(Eigen::Vector3d(0.02, 0.1, 0)) * k1.T_w_c.so3(),
                     k1.T_w_c.translation() + Eigen::Vector3d(0, 0.3, 0), 1.5);
  EXPECT_EQ(store.applyCorrection({{0, Sim3d(store.keyframe(0).T_w_c)}, {1, S1_new}}), 5);
  const Sim3d move = S1_new * S1.inverse();
  for (const auto& [id, S_old] : {std::pair<int, Sim3d>{2, S2}, {3, S3}}) {
    const KeyframeRecord k = store.keyframe(id);
    const Sim3d expected = move * S_old;
    EXPECT_LT((k.T_w_c.translation() - expected.translation()).norm(), 1e-12) << id;
    EXPECT_NEAR(k.scale, 1.5, 1e-12) << id;
    // Its pose relative to the keyframe it follows is kept.
    const Sim3d rel = Sim3d(store.keyframe(1).T_w_c.so3(), store.keyframe(1).T_w_c.translation(),
                            store.keyframe(1).scale)
                          .inverse() *
                      Sim3d(k.T_w_c.so3(), k.T_w_c.translation(), k.scale);
    EXPECT_LT(((S1.inverse() * S_old).matrix() - rel.matrix()).norm(), 1e-9) << id;
  }
  // 4 follows 0, which did not move.
  EXPECT_LT((store.keyframe(4).T_w_c.translation() - Eigen::Vector3d(4, 0, 0)).norm(), 1e-12);
  // Frames tracked against a folded keyframe move with it.
  const Trajectory frames = store.frameTrajectory();
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_LT((frames[0].pose.translation - (move * S3) * Eigen::Vector3d(0, 0, 0.5)).norm(), 1e-9);
  // A later correction that leaves 1 alone leaves its followers alone.
  const KeyframeRecord before = store.keyframe(3);
  store.applyCorrection({{0, Sim3d(SE3d(SO3d(), Eigen::Vector3d(0, 0, 0.1)))}});
  EXPECT_LT((store.keyframe(3).T_w_c.translation() - before.T_w_c.translation()).norm(), 1e-12);
  EXPECT_GT((store.keyframe(4).T_w_c.translation() - Eigen::Vector3d(4, 0, 0)).norm(), 0.05);
}

}  // namespace
}  // namespace ldsm
