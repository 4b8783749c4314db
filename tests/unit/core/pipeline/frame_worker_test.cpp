// The System's input stage (core/src/pipeline/frame_worker.h). Inline (deterministic mode): the
// handler runs inside push(), on the caller's image, and its exceptions reach the caller.
// Threaded, under stress: 20 000 small frames
// from a producer to the tracking thread through the frame pool and the lock-free queue, with
// random stalls on both sides. Offline: nothing lost, duplicated or reordered, and every pixel of
// every frame intact (a buffer reused while still queued would show). Live: received + dropped
// == submitted, in order, the newest frame never dropped.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <random>
#include <thread>
#include <vector>

#include "ldsm/error.h"
#include "pipeline/frame_worker.h"

namespace ldsm {
namespace {

constexpr int kW = 32;
constexpr int kH = 24;
constexpr int kFrames = 20000;

std::uint8_t pixel(std::int64_t frame, int x, int y) {
  return static_cast<std::uint8_t>((frame * 31 + x * 7 + y * 13) & 0xFF);
}

void maybeStall(std::mt19937& rng) {
  const unsigned r = rng() % 1000;
  if (r < 2)
    std::this_thread::sleep_for(std::chrono::microseconds(200 + rng() % 800));
  else if (r < 20)
    std::this_thread::yield();
}

struct Received {
  std::vector<std::int64_t> frames;  ///< frame numbers in the order received
  std::atomic<int> corrupt{0};
};

/// Pushes kFrames frames whose timestamp is their number and whose pixels encode it.
void runStress(bool live, Received& received, FrameWorkerCounts& counts) {
  received.frames.reserve(kFrames);
  std::mt19937 consumer_rng(7);
  FrameWorkerOptions options;
  options.pool_size = 6;
  options.width = kW;
  options.height = kH;
  options.live = live;
  FrameWorker worker(
      [&](const FrameView& f, std::int64_t) {
        const auto n = static_cast<std::int64_t>(f.timestamp);
        for (int y = 0; y < kH; ++y)
          for (int x = 0; x < kW; ++x)
            if (f.image(x, y) != pixel(n, x, y)) {
              ++received.corrupt;
              y = kH;
              break;
            }
        received.frames.push_back(n);
        maybeStall(consumer_rng);
      },
      options);
  std::mt19937 producer_rng(11);
  ImageU8 image(kW, kH);
  for (std::int64_t n = 0; n < kFrames; ++n) {
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) image(x, y) = pixel(n, x, y);
    worker.push({image.view(), static_cast<double>(n)});
    maybeStall(producer_rng);
  }
  worker.drain();
  counts = worker.counts();
}

TEST(FrameWorkerStress, OfflineLosesNothingAndKeepsOrderAndPixels) {
  Received r;
  FrameWorkerCounts c;
  runStress(false, r, c);
  EXPECT_EQ(c.submitted, kFrames);
  EXPECT_EQ(c.dropped, 0);
  EXPECT_EQ(c.processed, kFrames);
  ASSERT_EQ(r.frames.size(), static_cast<std::size_t>(kFrames));
  for (std::int64_t n = 0; n < kFrames; ++n) ASSERT_EQ(r.frames[n], n);
  EXPECT_EQ(r.corrupt.load(), 0);
  EXPECT_LE(c.max_queue_depth, c.queue_capacity);
}

TEST(FrameWorkerStress, LiveDropsOnlyAndAccountsForEveryFrame) {
  Received r;
  FrameWorkerCounts c;
  runStress(true, r, c);
  EXPECT_EQ(c.submitted, kFrames);
  EXPECT_EQ(c.processed + c.dropped, kFrames);
  ASSERT_EQ(r.frames.size(), static_cast<std::size_t>(c.processed));
  for (std::size_t i = 1; i < r.frames.size(); ++i) ASSERT_GT(r.frames[i], r.frames[i - 1]);
  EXPECT_EQ(r.frames.back(), kFrames - 1);  // the newest frame is never dropped
  EXPECT_EQ(r.corrupt.load(), 0);
  EXPECT_GT(c.dropped, 0);  // the consumer stalls: the producer outruns it
  std::printf("live: %lld received, %lld dropped, mean queue depth %.2f\n",
              static_cast<long long>(c.processed), static_cast<long long>(c.dropped),
              c.mean_queue_depth);
}

TEST(FrameWorkerStress, PoolSmallerThanFourIsAConfigError) {
  FrameWorkerOptions options;
  options.pool_size = 3;
  options.width = kW;
  options.height = kH;
  EXPECT_THROW(FrameWorker([](const FrameView&, std::int64_t) {}, options), ConfigError);
}

TEST(FrameWorkerInline, RunsTheHandlerInsidePushOnTheCallersImage) {
  FrameWorkerOptions options;
  options.mode = concurrency::TaskMode::kInline;
  options.pool_size = 0;  // unused inline: no pool, no queue, no thread
  ImageU8 image(kW, kH);
  image(3, 4) = 77;
  std::vector<std::int64_t> seen;
  const std::thread::id caller = std::this_thread::get_id();
  FrameWorker worker(
      [&](const FrameView& f, std::int64_t enqueued_ns) {
        EXPECT_EQ(std::this_thread::get_id(), caller);
        EXPECT_EQ(f.image.data, image.view().data) << "no copy";
        EXPECT_LE(enqueued_ns, steadyNowNs());
        if (f.timestamp < 0) throw InputError("negative");
        seen.push_back(static_cast<std::int64_t>(f.timestamp));
      },
      options);
  EXPECT_FALSE(worker.queued());
  for (int n = 0; n < 5; ++n) {
    worker.push({image.view(), static_cast<double>(n)});
    ASSERT_EQ(seen.size(), static_cast<std::size_t>(n + 1)) << "processed before push() returns";
  }
  EXPECT_THROW(worker.push({image.view(), -1.0}), InputError);
  worker.drain();
  const FrameWorkerCounts c = worker.counts();
  EXPECT_EQ(c.submitted, 6);
  EXPECT_EQ(c.processed, 5);
  EXPECT_EQ(c.dropped, 0);
  EXPECT_EQ(c.queue_capacity, 0);
  EXPECT_EQ(c.max_queue_depth, 0);
  EXPECT_DOUBLE_EQ(c.mean_queue_depth, 0.0);
  worker.stop();
  worker.push({image.view(), 9.0});
  EXPECT_EQ(seen.size(), 5u) << "nothing after stop()";
}

}  // namespace
}  // namespace ldsm
