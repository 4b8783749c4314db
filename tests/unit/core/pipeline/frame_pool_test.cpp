// FramePool: every buffer preallocated at the pool's size, acquire/release by index, exhaustion,
// misuse detection, and no reallocation when a frame of the pool's size is written.
#include "pipeline/frame_pool.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <vector>

#include "ldsm/error.h"

namespace ldsm::pipeline {
namespace {

TEST(FramePool, RejectsBadSizes) {
  EXPECT_THROW(FramePool(0, 64, 48), ConfigError);
  EXPECT_THROW(FramePool(5000, 64, 48), ConfigError);
  EXPECT_THROW(FramePool(4, 0, 48), ConfigError);
  EXPECT_THROW(FramePool(4, 64, -1), ConfigError);
}

TEST(FramePool, HandsOutEveryBufferOnceThenRunsOut) {
  FramePool pool(5, 64, 48);  // not a power of two: the free list rounds up
  EXPECT_EQ(pool.size(), 5u);
  EXPECT_EQ(pool.freeCount(), 5u);
  std::set<int> taken;
  for (int k = 0; k < 5; ++k) {
    const int i = pool.tryAcquire();
    ASSERT_GE(i, 0);
    ASSERT_LT(i, 5);
    EXPECT_TRUE(taken.insert(i).second) << "buffer " << i << " handed out twice";
    EXPECT_EQ(pool.image(i).width(), 64);
    EXPECT_EQ(pool.image(i).height(), 48);
  }
  EXPECT_EQ(pool.tryAcquire(), -1);
  EXPECT_EQ(pool.freeCount(), 0u);
  pool.release(3);
  EXPECT_EQ(pool.freeCount(), 1u);
  EXPECT_EQ(pool.tryAcquire(), 3);
}

TEST(FramePool, SingleBufferPool) {
  FramePool pool(1, 8, 8);
  const int i = pool.tryAcquire();
  EXPECT_EQ(i, 0);
  EXPECT_EQ(pool.tryAcquire(), -1);
  pool.release(i);
  EXPECT_EQ(pool.tryAcquire(), 0);
}

TEST(FramePool, ReleaseOfABufferNotInUseThrows) {
  FramePool pool(2, 8, 8);
  EXPECT_THROW(pool.release(0), Error);  // never acquired
  const int i = pool.tryAcquire();
  pool.release(i);
  EXPECT_THROW(pool.release(i), Error);  // twice
  EXPECT_THROW(pool.release(-1), Error);
  EXPECT_THROW(pool.release(2), Error);
  EXPECT_EQ(pool.freeCount(), 2u);
}

TEST(FramePool, BuffersAreDistinctAndKeepTheirMemory) {
  FramePool pool(3, 32, 16);
  std::vector<const std::uint8_t*> data;
  for (int k = 0; k < 3; ++k) {
    const int i = pool.tryAcquire();
    data.push_back(pool.image(i).data());
    ImageU8& image = pool.image(i);
    image.resize(32, 16);  // a frame of the pool's size: no reallocation
    image.fill(static_cast<std::uint8_t>(10 * i));
    EXPECT_EQ(image.data(), data.back());
  }
  std::sort(data.begin(), data.end());
  EXPECT_TRUE(std::adjacent_find(data.begin(), data.end()) == data.end());
  for (int i = 0; i < 3; ++i) EXPECT_EQ(pool.image(i)(31, 15), 10 * i);
}

}  // namespace
}  // namespace ldsm::pipeline
