// A bounded frame history: frames beyond it leave the frame log with the poses they had when they
// left, wait for takeRetiredFrames(), and are not moved by later corrections; what nobody takes
// is dropped and counted, so memory stays bounded either way.
#include <gtest/gtest.h>

#include "map/map_store.h"

namespace ldsm {
namespace {

constexpr std::size_t kChunk = MapStore::kFrameChunk;

FrameRecord frameAt(std::int64_t i) {
  return {i, 0.01 * static_cast<double>(i), 0, SE3d(SO3d(), Eigen::Vector3d(0, 0, 0.001 * i))};
}

TEST(MapStoreFrames, FramesBeyondTheHistoryLeaveWithThePosesTheyHadThen) {
  MapStore store;
  store.setFrameHistory(1000);
  store.setKeyframe({0, 0, 0.0, SE3d(SO3d(), Eigen::Vector3d(1, 0, 0))});
  const std::int64_t n = static_cast<std::int64_t>(kChunk) + 999;  // not a chunk beyond yet
  for (std::int64_t i = 0; i < n; ++i) store.addFrame(frameAt(i));
  EXPECT_EQ(store.retireFrames(), 0u);
  EXPECT_EQ(store.frameTrajectory().size(), static_cast<std::size_t>(n));
  store.addFrame(frameAt(n));  // now the oldest chunk is beyond the newest 1000 frames
  EXPECT_EQ(store.retireFrames(), kChunk);
  EXPECT_EQ(store.retiredFrameCount(), static_cast<std::int64_t>(kChunk));

  // The keyframe moves after they left: the frames in memory move with it, the retired do not.
  store.applyCorrection({{0, Sim3d(SE3d(SO3d(), Eigen::Vector3d(2, 0, 0)))}});
  const Trajectory retired = store.takeRetiredFrames();
  const Trajectory kept = store.frameTrajectory();
  ASSERT_EQ(retired.size(), kChunk);
  ASSERT_EQ(kept.size(), static_cast<std::size_t>(n + 1) - kChunk);
  for (std::size_t i = 0; i < retired.size(); ++i) {
    EXPECT_EQ(retired[i].timestamp, 0.01 * static_cast<double>(i));
    EXPECT_NEAR((retired[i].pose.translation - Eigen::Vector3d(1, 0, 0.001 * i)).norm(), 0, 1e-12);
  }
  EXPECT_EQ(kept.front().timestamp, 0.01 * static_cast<double>(kChunk));  // continues them
  EXPECT_NEAR(kept.front().pose.translation.x(), 2.0, 1e-12);
  EXPECT_TRUE(store.takeRetiredFrames().empty());  // each handed out once
}

TEST(MapStoreFrames, WithoutAHistoryEveryFrameStays) {
  MapStore store;
  store.setKeyframe({0, 0, 0.0, SE3d()});
  for (std::int64_t i = 0; i < static_cast<std::int64_t>(3 * kChunk); ++i)
    store.addFrame(frameAt(i));
  EXPECT_EQ(store.retireFrames(), 0u);
  EXPECT_EQ(store.frameTrajectory().size(), 3 * kChunk);
  EXPECT_EQ(store.retiredFrameCount(), 0);
}

TEST(MapStoreFrames, RetiredFramesNobodyTakesAreDroppedAndCounted) {
  MapStore store;
  store.setFrameHistory(1);
  store.setKeyframe({0, 0, 0.0, SE3d()});
  const std::size_t chunks = MapStore::kRetiredBacklog + 3;
  for (std::size_t c = 0; c < chunks; ++c) {
    for (std::size_t i = 0; i < kChunk; ++i)
      store.addFrame(frameAt(static_cast<std::int64_t>(c * kChunk + i)));
    store.retireFrames();
  }
  // The last chunk is still within the history of one frame's chunk.
  EXPECT_EQ(store.retiredFrameCount(), static_cast<std::int64_t>((chunks - 1) * kChunk));
  EXPECT_EQ(store.lostRetiredFrameCount(), static_cast<std::int64_t>(2 * kChunk));
  const Trajectory waiting = store.takeRetiredFrames();
  ASSERT_EQ(waiting.size(), MapStore::kRetiredBacklog * kChunk);
  EXPECT_EQ(waiting.front().timestamp, 0.01 * static_cast<double>(2 * kChunk));  // the newest
  EXPECT_EQ(store.frameTrajectory().size(), kChunk);
}

}  // namespace
}  // namespace ldsm
