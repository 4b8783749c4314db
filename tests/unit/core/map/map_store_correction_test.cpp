// Loop corrections move keyframes that left the window, with their frames and points.
#include <gtest/gtest.h>

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
  EXPECT_LT((pts[0].position - S1_new * Eigen::Vector3d(0, 0, 2)).norm(), 1e-9);
  EXPECT_LT((pts[1].position - q.position).norm(), 1e-12);
  EXPECT_LT((pts[2].position - r.position).norm(), 1e-12);
}

}  // namespace
}  // namespace ldsm
