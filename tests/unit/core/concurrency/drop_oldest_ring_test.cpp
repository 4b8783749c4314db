// DropOldestRing single-threaded: it behaves as a FIFO until full; then tryPush fails and
// pushDroppingOldest replaces exactly the oldest element, counting each drop.
#include "concurrency/drop_oldest_ring.h"

#include <gtest/gtest.h>

#include <atomic>
#include <vector>

#include "concurrency/ring_wait.h"
#include "ldsm/error.h"

namespace ldsm::concurrency {
namespace {

std::vector<int> drain(DropOldestRing<int>& ring) {
  std::vector<int> out;
  int v = 0;
  while (ring.tryPop(v)) out.push_back(v);
  return out;
}

TEST(DropOldestRing, RejectsCapacityThatIsNotAPowerOfTwo) {
  EXPECT_THROW(DropOldestRing<int>(6), ConfigError);
  EXPECT_THROW(DropOldestRing<int>(0), ConfigError);
}

TEST(DropOldestRing, IsAFifoWhileNotFull) {
  DropOldestRing<int> ring(4);
  int dropped = -1;
  EXPECT_FALSE(ring.pushDroppingOldest(10, dropped));
  EXPECT_TRUE(ring.tryPush(11));
  EXPECT_FALSE(ring.pushDroppingOldest(12, dropped));
  EXPECT_EQ(dropped, -1);
  EXPECT_EQ(ring.size(), 3u);
  EXPECT_EQ(drain(ring), (std::vector<int>{10, 11, 12}));
  EXPECT_EQ(ring.droppedCount(), 0u);
  EXPECT_TRUE(ring.empty());
}

TEST(DropOldestRing, TryPushFailsWhenFull) {
  DropOldestRing<int> ring(2);
  ASSERT_TRUE(ring.tryPush(1));
  ASSERT_TRUE(ring.tryPush(2));
  EXPECT_FALSE(ring.tryPush(3));
  EXPECT_EQ(drain(ring), (std::vector<int>{1, 2}));
  EXPECT_EQ(ring.droppedCount(), 0u);
}

TEST(DropOldestRing, DropsExactlyTheOldestWhenFull) {
  DropOldestRing<int> ring(4);
  for (int i = 0; i < 4; ++i) ASSERT_TRUE(ring.tryPush(i));
  int dropped = -1;
  EXPECT_TRUE(ring.pushDroppingOldest(4, dropped));
  EXPECT_EQ(dropped, 0);
  EXPECT_TRUE(ring.pushDroppingOldest(5, dropped));
  EXPECT_EQ(dropped, 1);
  EXPECT_EQ(ring.droppedCount(), 2u);
  EXPECT_EQ(ring.size(), 4u);
  EXPECT_EQ(drain(ring), (std::vector<int>{2, 3, 4, 5}));
}

TEST(DropOldestRing, KeepsTheNewestCapacityElementsOfALongBurst) {
  DropOldestRing<int> ring(8);
  std::vector<int> dropped_values;
  for (int i = 0; i < 1000; ++i) {
    int dropped = -1;
    if (ring.pushDroppingOldest(i, dropped)) dropped_values.push_back(dropped);
    if (i % 97 == 0) {  // the consumer takes one now and then
      int v = 0;
      ASSERT_TRUE(ring.tryPop(v));
    }
  }
  EXPECT_EQ(ring.droppedCount(), dropped_values.size());
  // Dropped values are increasing (always the oldest) and the survivors are the last 8.
  for (std::size_t k = 1; k < dropped_values.size(); ++k)
    ASSERT_LT(dropped_values[k - 1], dropped_values[k]);
  std::vector<int> expected;
  for (int i = 992; i < 1000; ++i) expected.push_back(i);
  EXPECT_EQ(drain(ring), expected);
  // Every value is accounted for exactly once: popped in the loop, dropped, or drained.
  const std::size_t popped_in_loop = 1000 / 97 + 1;
  EXPECT_EQ(popped_in_loop + dropped_values.size() + expected.size(), 1000u);
}

TEST(DropOldestRing, SmallestRingOfTwoKeepsTheTwoNewest) {
  EXPECT_THROW(DropOldestRing<int>(1), ConfigError);  // sequence numbers need two slots
  DropOldestRing<int> ring(2);
  int dropped = -1;
  EXPECT_FALSE(ring.pushDroppingOldest(1, dropped));
  EXPECT_FALSE(ring.pushDroppingOldest(2, dropped));
  EXPECT_TRUE(ring.pushDroppingOldest(3, dropped));
  EXPECT_EQ(dropped, 1);
  EXPECT_TRUE(ring.pushDroppingOldest(4, dropped));
  EXPECT_EQ(dropped, 2);
  EXPECT_EQ(drain(ring), (std::vector<int>{3, 4}));
  EXPECT_EQ(ring.droppedCount(), 2u);
}

TEST(DropOldestRing, PushWithPolicyWaitsOrDrops) {
  DropOldestRing<int> ring(2);
  const std::atomic<bool> stop{true};  // a waiting push gives up at once
  int dropped = -1;
  EXPECT_EQ(pushWithPolicy(ring, 1, OverflowPolicy::Wait, stop, dropped), PushOutcome::Pushed);
  EXPECT_EQ(pushWithPolicy(ring, 2, OverflowPolicy::Wait, stop, dropped), PushOutcome::Pushed);
  EXPECT_EQ(pushWithPolicy(ring, 3, OverflowPolicy::Wait, stop, dropped), PushOutcome::Stopped);
  EXPECT_EQ(ring.droppedCount(), 0u);
  EXPECT_EQ(pushWithPolicy(ring, 4, OverflowPolicy::DropOldest, stop, dropped),
            PushOutcome::PushedDroppingOldest);
  EXPECT_EQ(dropped, 1);
  EXPECT_EQ(ring.droppedCount(), 1u);
  EXPECT_EQ(drain(ring), (std::vector<int>{2, 4}));
}

}  // namespace
}  // namespace ldsm::concurrency
