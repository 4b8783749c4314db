// SpscRing: capacity rules, FIFO order, full/empty behaviour and wrap-around, single-threaded.
#include "concurrency/spsc_ring.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "ldsm/error.h"

namespace ldsm::concurrency {
namespace {

TEST(SpscRing, RejectsCapacityThatIsNotAPowerOfTwo) {
  EXPECT_THROW(SpscRing<int>(0), ConfigError);
  EXPECT_THROW(SpscRing<int>(3), ConfigError);
  EXPECT_THROW(SpscRing<int>(12), ConfigError);
  EXPECT_NO_THROW(SpscRing<int>(1));
  EXPECT_NO_THROW(SpscRing<int>(16));
}

TEST(SpscRing, PopFromEmptyFailsAndLeavesOutputUntouched) {
  SpscRing<int> ring(4);
  int out = 42;
  EXPECT_FALSE(ring.tryPop(out));
  EXPECT_EQ(out, 42);
  EXPECT_EQ(ring.size(), 0u);
  EXPECT_TRUE(ring.empty());
}

TEST(SpscRing, HoldsExactlyCapacityElementsInOrder) {
  SpscRing<int> ring(8);
  for (int i = 0; i < 8; ++i) {
    ASSERT_TRUE(ring.tryPush(i));
    EXPECT_EQ(ring.size(), static_cast<std::size_t>(i + 1));
  }
  EXPECT_FALSE(ring.tryPush(99));
  EXPECT_EQ(ring.size(), 8u);
  for (int i = 0; i < 8; ++i) {
    int out = -1;
    ASSERT_TRUE(ring.tryPop(out));
    EXPECT_EQ(out, i);
  }
  int out = -1;
  EXPECT_FALSE(ring.tryPop(out));
}

TEST(SpscRing, WrapsAroundManyTimes) {
  SpscRing<int> ring(4);
  int next_in = 0;
  int next_out = 0;
  // Alternate bursts of 1..4 pushes and pops: the indices wrap the 4 slots hundreds of times.
  for (int round = 0; round < 1000; ++round) {
    const int burst = 1 + round % 4;
    for (int k = 0; k < burst; ++k) ASSERT_TRUE(ring.tryPush(next_in++));
    for (int k = 0; k < burst; ++k) {
      int out = -1;
      ASSERT_TRUE(ring.tryPop(out));
      ASSERT_EQ(out, next_out++);
    }
  }
  EXPECT_TRUE(ring.empty());
}

TEST(SpscRing, FailedPushDoesNotMoveFromTheValue) {
  SpscRing<std::unique_ptr<int>> ring(1);
  ASSERT_TRUE(ring.tryPush(std::make_unique<int>(1)));
  auto second = std::make_unique<int>(2);
  EXPECT_FALSE(ring.tryPush(std::move(second)));
  ASSERT_NE(second, nullptr);  // NOLINT(bugprone-use-after-move): untouched by contract
  EXPECT_EQ(*second, 2);
  std::unique_ptr<int> out;
  ASSERT_TRUE(ring.tryPop(out));
  EXPECT_EQ(*out, 1);
  EXPECT_TRUE(ring.tryPush(std::move(second)));
}

TEST(SpscRing, CarriesNonTrivialValues) {
  SpscRing<std::string> ring(2);
  ASSERT_TRUE(ring.tryPush(std::string(100, 'a')));
  ASSERT_TRUE(ring.tryPush("b"));
  std::string out;
  ASSERT_TRUE(ring.tryPop(out));
  EXPECT_EQ(out, std::string(100, 'a'));
  ASSERT_TRUE(ring.tryPop(out));
  EXPECT_EQ(out, "b");
}

}  // namespace
}  // namespace ldsm::concurrency
