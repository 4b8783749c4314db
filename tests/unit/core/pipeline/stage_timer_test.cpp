// StageTimer: the summary's figures (count, mean, median, p99, max) from known samples, the ring
// of the newest `capacity` samples, and summaries taken while another thread records (lock-free:
// every summary is consistent with some prefix of the recorded samples).
#include "pipeline/stage_timer.h"

#include <gtest/gtest.h>

#include <atomic>
#include <thread>

namespace ldsm {
namespace {

TEST(StageTimer, SummarisesKnownSamples) {
  StageTimer timer({"a", "b"}, 1000);
  for (int i = 1; i <= 100; ++i) timer.record(0, i);
  const std::vector<StageTiming> s = timer.summary();
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0].stage, "a");
  EXPECT_EQ(s[0].count, 100);
  EXPECT_DOUBLE_EQ(s[0].mean_ms, 50.5);
  EXPECT_DOUBLE_EQ(s[0].p50_ms, 51.0);
  EXPECT_DOUBLE_EQ(s[0].p99_ms, 100.0);
  EXPECT_DOUBLE_EQ(s[0].max_ms, 100.0);
  EXPECT_EQ(s[1].stage, "b");
  EXPECT_EQ(s[1].count, 0);
  EXPECT_EQ(s[1].max_ms, 0.0);
}

TEST(StageTimer, PercentilesComeFromTheNewestSamples) {
  StageTimer timer({"a"}, 10);
  for (int i = 0; i < 10; ++i) timer.record(0, 1000.0);  // pushed out of the ring below
  for (int i = 0; i < 10; ++i) timer.record(0, 1.0);
  const StageTiming t = timer.summary()[0];
  EXPECT_EQ(t.count, 20);
  EXPECT_DOUBLE_EQ(t.p99_ms, 1.0);
  EXPECT_DOUBLE_EQ(t.max_ms, 1000.0);  // max and mean cover every sample
  EXPECT_DOUBLE_EQ(t.mean_ms, 500.5);
}

TEST(StageTimer, SummariesWhileAnotherThreadRecords) {
  StageTimer timer({"track"}, 20000);
  constexpr int kSamples = 100000;
  std::atomic<bool> done{false};
  std::atomic<bool> reading{false};
  std::thread writer([&] {
    while (!reading.load(std::memory_order_acquire)) std::this_thread::yield();
    for (int i = 0; i < kSamples; ++i) timer.record(0, 2.0);
    done.store(true, std::memory_order_release);
  });
  std::int64_t last = 0;
  reading.store(true, std::memory_order_release);
  do {
    const StageTiming t = timer.summary()[0];
    EXPECT_GE(t.count, last);
    last = t.count;
    if (t.count > 0) {
      EXPECT_DOUBLE_EQ(t.p50_ms, 2.0);
      EXPECT_DOUBLE_EQ(t.max_ms, 2.0);
    }
  } while (!done.load(std::memory_order_acquire));
  writer.join();
  const StageTiming t = timer.summary()[0];
  EXPECT_EQ(t.count, kSamples);
  EXPECT_DOUBLE_EQ(t.mean_ms, 2.0);
}

}  // namespace
}  // namespace ldsm
