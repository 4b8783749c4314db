// Stress tests of the rings and the frame pool: 100 000 items between two threads with random
// stalls on both sides (yields and short sleeps from a seeded generator, so that the ring is
// sometimes full and sometimes empty). Offline (waiting) mode must lose, duplicate and reorder
// nothing; live (drop-oldest) mode must keep the order and account for every item exactly once:
// received + dropped == sent. Also compiled into test_pipeline_tsan (ThreadSanitizer).
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <random>
#include <thread>
#include <vector>

#include "concurrency/drop_oldest_ring.h"
#include "concurrency/ring_wait.h"
#include "concurrency/spsc_ring.h"
#include "pipeline/frame_pool.h"

namespace ldsm::concurrency {
namespace {

using pipeline::FramePool;
using pipeline::FrameTicket;

constexpr std::int64_t kItems = 100000;

/// Random stalls: out of every 1024 calls on average `sleeps` sleep 20 us, `yields` yield.
class Staller {
 public:
  Staller(std::uint32_t seed, int yields, int sleeps)
      : rng_(seed), yields_(yields), sleeps_(sleeps) {}
  void maybeStall() {
    const int r = static_cast<int>(rng_() & 1023u);
    if (r < sleeps_) {
      std::this_thread::sleep_for(std::chrono::microseconds(20));
    } else if (r < sleeps_ + yields_) {
      std::this_thread::yield();
    }
  }

 private:
  std::mt19937 rng_;
  int yields_;
  int sleeps_;
};

/// Offline mode through any ring with tryPush/tryPop: everything arrives, once, in order.
template <typename Ring>
void expectLosslessInOrder(Ring& ring) {
  std::atomic<bool> end_of_stream{false};
  std::vector<std::int64_t> received;
  received.reserve(kItems);
  std::thread producer([&] {
    Staller staller(1, 24, 2);
    for (std::int64_t i = 0; i < kItems; ++i) {
      staller.maybeStall();
      pushWaiting(ring, i, std::atomic<bool>{false});
    }
    end_of_stream.store(true, std::memory_order_release);
  });
  Staller staller(2, 24, 2);
  std::int64_t v = 0;
  while (popWaiting(ring, v, end_of_stream)) {
    received.push_back(v);
    staller.maybeStall();
  }
  producer.join();

  ASSERT_EQ(static_cast<std::int64_t>(received.size()), kItems);
  std::int64_t out_of_place = 0;
  for (std::int64_t i = 0; i < kItems; ++i)
    if (received[static_cast<std::size_t>(i)] != i) ++out_of_place;
  EXPECT_EQ(out_of_place, 0);
}

TEST(RingStress, SpscRingOfflineLosesNothing) {
  SpscRing<std::int64_t> ring(8);
  expectLosslessInOrder(ring);
}

TEST(RingStress, DropOldestRingInOfflineModeLosesNothing) {
  DropOldestRing<std::int64_t> ring(8);
  expectLosslessInOrder(ring);
  EXPECT_EQ(ring.droppedCount(), 0u);
}

TEST(RingStress, DropOldestRingInLiveModeCountsEveryDrop) {
  DropOldestRing<std::int64_t> ring(8);
  std::atomic<bool> end_of_stream{false};
  std::vector<std::int64_t> received;
  std::vector<std::int64_t> dropped;
  received.reserve(kItems);
  dropped.reserve(kItems);
  std::thread producer([&] {
    Staller staller(3, 16, 1);
    std::int64_t old = 0;
    for (std::int64_t i = 0; i < kItems; ++i) {
      staller.maybeStall();
      if (ring.pushDroppingOldest(i, old)) dropped.push_back(old);
    }
    end_of_stream.store(true, std::memory_order_release);
  });
  Staller staller(4, 32, 8);  // a slower consumer: the ring overflows now and then
  std::int64_t v = 0;
  while (popWaiting(ring, v, end_of_stream)) {
    received.push_back(v);
    staller.maybeStall();
  }
  producer.join();

  EXPECT_GT(dropped.size(), 0u) << "the consumer never fell behind: the test proved nothing";
  EXPECT_GT(received.size(), 0u);
  EXPECT_EQ(ring.droppedCount(), dropped.size());
  EXPECT_EQ(static_cast<std::int64_t>(received.size() + ring.droppedCount()), kItems);
  EXPECT_TRUE(std::is_sorted(received.begin(), received.end()) &&
              std::adjacent_find(received.begin(), received.end()) == received.end())
      << "received out of order or twice";
  EXPECT_TRUE(std::is_sorted(dropped.begin(), dropped.end())) << "a drop was not the oldest";
  // Every item exactly once, received or dropped.
  std::vector<std::int64_t> all(received);
  all.insert(all.end(), dropped.begin(), dropped.end());
  std::sort(all.begin(), all.end());
  ASSERT_EQ(static_cast<std::int64_t>(all.size()), kItems);
  std::int64_t wrong = 0;
  for (std::int64_t i = 0; i < kItems; ++i)
    if (all[static_cast<std::size_t>(i)] != i) ++wrong;
  EXPECT_EQ(wrong, 0);
  EXPECT_EQ(received.back(), kItems - 1) << "the newest frame must never be dropped";
}

/// Capture -> tracking through the pool and a drop-oldest ring, as the live pipeline does: the
/// consumer checks every pixel of each frame it gets, so a buffer reused while still queued or
/// processed would show up as a wrong pixel.
void runPoolPipeline(bool live, std::int64_t items, std::int64_t& received, std::int64_t& bad,
                     std::uint64_t& drops) {
  constexpr std::size_t kCapacity = 4;
  DropOldestRing<FrameTicket> ring(kCapacity);
  FramePool pool(kCapacity + 2, 16, 8);  // ring + one being filled + one being processed
  std::atomic<bool> end_of_stream{false};
  std::atomic<std::int64_t> acquire_failures{0};
  received = 0;
  bad = 0;
  std::thread producer([&] {
    Staller staller(5, 16, 1);
    for (std::int64_t i = 0; i < items; ++i) {
      staller.maybeStall();
      FrameTicket ticket;
      ticket.buffer = pool.tryAcquire();
      if (ticket.buffer < 0) {
        acquire_failures.fetch_add(1);
        continue;
      }
      ticket.index = i;
      pool.image(ticket.buffer).fill(static_cast<std::uint8_t>(i % 251));
      if (live) {
        FrameTicket old;
        if (ring.pushDroppingOldest(ticket, old)) pool.release(old.buffer);
      } else {
        pushWaiting(ring, ticket, std::atomic<bool>{false});
      }
    }
    end_of_stream.store(true, std::memory_order_release);
  });
  Staller staller(6, 32, live ? 8 : 2);
  FrameTicket ticket;
  std::int64_t last_index = -1;
  while (popWaiting(ring, ticket, end_of_stream)) {
    const ImageU8& image = pool.image(ticket.buffer);
    const auto expected = static_cast<std::uint8_t>(ticket.index % 251);
    for (std::size_t k = 0; k < image.size(); ++k)
      if (image.data()[k] != expected) {
        ++bad;
        break;
      }
    if (ticket.index <= last_index) ++bad;
    last_index = ticket.index;
    ++received;
    staller.maybeStall();
    pool.release(ticket.buffer);
  }
  producer.join();
  drops = ring.droppedCount();
  EXPECT_EQ(acquire_failures.load(), 0);
  EXPECT_EQ(pool.freeCount(), pool.size()) << "a buffer was never released";
}

TEST(RingStress, FramePoolPipelineOfflineDeliversEveryFrameIntact) {
  std::int64_t received = 0, bad = 0;
  std::uint64_t drops = 0;
  runPoolPipeline(false, kItems, received, bad, drops);
  EXPECT_EQ(received, kItems);
  EXPECT_EQ(bad, 0);
  EXPECT_EQ(drops, 0u);
}

TEST(RingStress, FramePoolPipelineLiveDropsOldestAndNeverCorruptsAFrame) {
  std::int64_t received = 0, bad = 0;
  std::uint64_t drops = 0;
  runPoolPipeline(true, kItems, received, bad, drops);
  EXPECT_GT(drops, 0u);
  EXPECT_EQ(received + static_cast<std::int64_t>(drops), kItems);
  EXPECT_EQ(bad, 0);
}

}  // namespace
}  // namespace ldsm::concurrency
