// Maps in the store: keyframes of a map started after a loss are reported with its number, in
// its own frame, until a merge moves the earlier map into the current one's frame; then every pose
// is reported in the first map's frame again. And the map's budget: the most redundant kept
// keyframe is the one to give up first.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "map/map_store.h"

namespace ldsm {
namespace {

std::shared_ptr<MarginalizedKeyframe> data(int id) {
  auto kf = std::make_shared<MarginalizedKeyframe>();
  kf->id = id;
  return kf;
}

TEST(MapStoreMaps, SecondMapIsLabelledUntilMergedThenReportedInTheFirstMapsFrame) {
  MapStore store;
  const SE3d A0(SO3d(), Eigen::Vector3d(0, 0, 0));
  const SE3d A1(SO3d(), Eigen::Vector3d(1, 0, 0));
  store.setKeyframe({0, 0, 0.0, A0});
  store.setKeyframe({1, 10, 1.0, A1});
  store.addFrame({10, 1.0, 1, SE3d()});
  MapPoint pa;
  pa.position = Eigen::Vector3d(1, 0, 2);
  store.addPoints({{pa, 1}});
  // Tracking lost for good: map 1, in a frame of its own (here: shifted and half the scale).
  EXPECT_EQ(store.startNewMap(), 1);
  EXPECT_EQ(store.currentMap(), 1);
  const SE3d B2(SO3d(), Eigen::Vector3d(10, 0, 0));
  store.setKeyframe({2, 20, 2.0, B2});
  store.addFrame({20, 2.0, 2, SE3d()});
  EXPECT_FALSE(store.inCurrentMap(1));
  EXPECT_TRUE(store.inCurrentMap(2));
  Trajectory t = store.frameTrajectory();
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[0].map, 0);
  EXPECT_EQ(t[1].map, 1);
  EXPECT_FALSE(store.inFirstMap(1));

  // A loop: map 0 in map 1's coordinates is S_10 * x (scale 0.5, shifted by 10 along x).
  const Sim3d S_10(SO3d(), Eigen::Vector3d(10, 0, 0), 0.5);
  std::map<int, Sim3d> moved;
  for (const int id : {0, 1}) {
    const SE3d T = id == 0 ? A0 : A1;
    moved[id] = S_10 * Sim3d(T);
  }
  EXPECT_EQ(store.mergeMaps(0, 1, S_10, moved), 2);
  EXPECT_TRUE(store.inFirstMap(1));
  EXPECT_TRUE(store.inCurrentMap(1));
  t = store.frameTrajectory();
  ASSERT_EQ(t.size(), 2u);
  // Map 0's frame is where poses are reported: the first frame is back where it was, and map 1's
  // keyframe (at 10 in map 1) is at S_10^-1 * 10 = 0 in map 0's frame.
  EXPECT_EQ(t[0].map, 0);
  EXPECT_EQ(t[1].map, 0);
  EXPECT_LT((t[0].pose.translation - A1.translation()).norm(), 1e-12);
  EXPECT_LT((t[1].pose.translation - Eigen::Vector3d(0, 0, 0)).norm(), 1e-12);
  const std::vector<MapPoint> points = store.points();
  ASSERT_EQ(points.size(), 1u);
  EXPECT_EQ(points[0].map, 0);
  EXPECT_LT((points[0].position - pa.position).norm(), 1e-12);
}

TEST(MapStoreMaps, MostRedundantKeyframeIsTheNearestToAnotherLookingTheSameWay) {
  MapStore store;
  // 0 and 1 stand 0.1 apart looking the same way; 2 stands 0.05 from 1 but looks back; 3 is alone.
  const SO3d back = SO3d::exp(Eigen::Vector3d(0, M_PI, 0));
  store.setKeyframe({0, 0, 0.0, SE3d(SO3d(), Eigen::Vector3d(0, 0, 0))});
  store.setKeyframe({1, 1, 0.1, SE3d(SO3d(), Eigen::Vector3d(0.1, 0, 0))});
  store.setKeyframe({2, 2, 0.2, SE3d(back, Eigen::Vector3d(0.15, 0, 0))});
  store.setKeyframe({3, 3, 0.3, SE3d(SO3d(), Eigen::Vector3d(5, 0, 0))});
  for (int id = 0; id < 4; ++id) store.setKeyframeData(data(id));
  const double angle = 30.0 * M_PI / 180.0;
  EXPECT_EQ(store.mostRedundantKeyframe(angle, {}), 0) << "of the pair 0-1, the older";
  EXPECT_EQ(store.mostRedundantKeyframe(angle, {0}), 1);
  store.cullKeyframe(0);
  // 1's only neighbour looking its way is 3, far; 2 looks back and has no partner: 1 or 3.
  const int next = store.mostRedundantKeyframe(angle, {});
  EXPECT_TRUE(next == 1 || next == 3) << next;
  EXPECT_EQ(store.dataKeyframeCount(), 3u);
}

TEST(MapStoreMaps, ACulledKeyframeNeverComesBackIntoTheCovisibilityGraph) {
  // A loop is found from a keyframe after it was culled (the loop closer sees every keyframe
  // that leaves the window, culled or kept): the edge would bring it back as a vertex that no
  // cull removes again, one more per loop, and join the map keyframes through it.
  MapStore store;
  for (int id = 0; id < 3; ++id) {
    store.setKeyframe({id, id, 0.1 * id, SE3d(SO3d(), Eigen::Vector3d(id, 0, 0))});
    store.setKeyframeData(data(id));
  }
  store.connect(0, 1);
  EXPECT_EQ(store.covisibleNeighbourhood({0}, 2, 10), std::vector<int>({1}));
  store.cullKeyframe(1);
  EXPECT_TRUE(store.covisibleNeighbourhood({0}, 2, 10).empty());
  store.connect(1, 2);  // the loop found from the culled keyframe
  store.connect(0, 1);
  EXPECT_TRUE(store.covisibleNeighbourhood({0}, 2, 10).empty());
  EXPECT_TRUE(store.covisibleNeighbourhood({2}, 2, 10).empty());
  EXPECT_TRUE(store.firstMap().covisibility.empty());
  store.connect(0, 2);
  EXPECT_EQ(store.covisibleNeighbourhood({0}, 2, 10), std::vector<int>({2}));
  ASSERT_EQ(store.firstMap().covisibility.size(), 1u);
}

}  // namespace
}  // namespace ldsm
