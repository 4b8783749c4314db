// MpmcRing: FIFO semantics single-threaded, and no loss or duplication with two producers and two
// consumers.
#include "concurrency/mpmc_ring.h"

#include <gtest/gtest.h>

#include <atomic>
#include <thread>
#include <vector>

#include "ldsm/error.h"

namespace ldsm::concurrency {
namespace {

TEST(MpmcRing, FifoFullAndEmpty) {
  EXPECT_THROW(MpmcRing<int>(5), ConfigError);
  EXPECT_THROW(MpmcRing<int>(1), ConfigError);
  MpmcRing<int> ring(4);
  int out = -1;
  EXPECT_FALSE(ring.tryPop(out));
  for (int i = 0; i < 4; ++i) ASSERT_TRUE(ring.tryPush(i));
  EXPECT_FALSE(ring.tryPush(4));
  EXPECT_EQ(ring.size(), 4u);
  for (int i = 0; i < 4; ++i) {
    ASSERT_TRUE(ring.tryPop(out));
    EXPECT_EQ(out, i);
  }
  EXPECT_FALSE(ring.tryPop(out));
  EXPECT_EQ(ring.size(), 0u);
}

TEST(MpmcRing, TwoProducersTwoConsumersLoseAndDuplicateNothing) {
  constexpr int kPerProducer = 20000;
  MpmcRing<int> ring(16);
  std::vector<std::atomic<int>> seen(2 * kPerProducer);
  for (auto& s : seen) s.store(0);
  std::atomic<int> consumed{0};

  auto produce = [&](int first) {
    for (int i = first; i < first + kPerProducer; ++i)
      while (!ring.tryPush(i)) std::this_thread::yield();
  };
  auto consume = [&] {
    int v = 0;
    while (consumed.load() < 2 * kPerProducer) {
      if (ring.tryPop(v)) {
        seen[static_cast<std::size_t>(v)].fetch_add(1);
        consumed.fetch_add(1);
      } else {
        std::this_thread::yield();
      }
    }
  };
  std::thread p1(produce, 0), p2(produce, kPerProducer), c1(consume), c2(consume);
  p1.join();
  p2.join();
  c1.join();
  c2.join();
  for (std::size_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i].load(), 1) << "value " << i;
  EXPECT_EQ(consumed.load(), 2 * kPerProducer);
}

}  // namespace
}  // namespace ldsm::concurrency
