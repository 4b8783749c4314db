// AppendOnlyLog: records in order across chunk boundaries, reserve() and a full log, and a reader
// that copies the log while the writer appends: it must see a prefix, every record whole, and the
// writer must never wait for it (the log has no lock to wait on). Also built under
// ThreadSanitizer (test_pipeline_tsan).
#include "concurrency/append_only_log.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <thread>
#include <vector>

namespace ldsm::concurrency {
namespace {

struct Record {
  std::int64_t index = -1;
  std::int64_t twice = 0;  // 2 * index
  double third = 0.0;      // index / 3
};

Record makeRecord(std::int64_t i) {
  return {i, 2 * i, static_cast<double>(i) / 3.0};
}

TEST(AppendOnlyLog, KeepsRecordsInOrderAcrossChunks) {
  AppendOnlyLog<Record, 8> log(16);
  EXPECT_EQ(log.size(), 0u);
  EXPECT_EQ(log.capacity(), 128u);
  for (std::int64_t i = 0; i < 100; ++i) log.push(makeRecord(i));
  ASSERT_EQ(log.size(), 100u);
  for (std::size_t i = 0; i < log.size(); ++i) EXPECT_EQ(log[i].index, static_cast<int>(i));
  std::int64_t expected = 0;
  log.forEach([&](const Record& r) { EXPECT_EQ(r.index, expected++); });
  EXPECT_EQ(expected, 100);
}

TEST(AppendOnlyLog, AFullLogThrowsAndKeepsWhatItHas) {
  AppendOnlyLog<Record, 4> log(2);
  for (std::int64_t i = 0; i < 8; ++i) log.push(makeRecord(i));
  EXPECT_THROW(log.push(makeRecord(8)), Error);
  EXPECT_EQ(log.size(), 8u);
  EXPECT_EQ(log[7].index, 7);
  log.reserve(1000);  // clamped to the capacity, no throw
}

TEST(AppendOnlyLog, ReservedChunksAreUsed) {
  AppendOnlyLog<Record, 4> log(8);
  log.reserve(10);  // chunks 0..2
  for (std::int64_t i = 0; i < 12; ++i) log.push(makeRecord(i));
  EXPECT_EQ(log.size(), 12u);
  EXPECT_EQ(log[11].twice, 22);
}

TEST(AppendOnlyLog, AReaderSeesWholeRecordsInOrderWhileTheWriterAppends) {
  constexpr std::int64_t kRecords = 200000;
  AppendOnlyLog<Record, 64> log(kRecords / 64 + 1);
  std::atomic<bool> done{false};
  std::atomic<std::int64_t> bad{0};
  std::atomic<std::int64_t> reads{0};
  std::thread reader([&] {
    std::size_t last = 0;
    while (!done.load(std::memory_order_acquire) || last < log.size()) {
      std::size_t seen = 0;
      log.forEach([&](const Record& r) {
        if (r.index != static_cast<std::int64_t>(seen) || r.twice != 2 * r.index ||
            r.third != static_cast<double>(r.index) / 3.0)
          bad.fetch_add(1, std::memory_order_relaxed);
        ++seen;
      });
      if (seen < last) bad.fetch_add(1, std::memory_order_relaxed);  // the log never shrinks
      last = seen;
      reads.fetch_add(1, std::memory_order_relaxed);
    }
  });
  for (std::int64_t i = 0; i < kRecords; ++i) log.push(makeRecord(i));
  done.store(true, std::memory_order_release);
  reader.join();
  EXPECT_EQ(bad.load(), 0);
  EXPECT_GE(reads.load(), 1);
  EXPECT_EQ(log.size(), static_cast<std::size_t>(kRecords));
}

TEST(AppendOnlyLog, ReleasedChunksGoAndTheRestKeepTheirIndices) {
  AppendOnlyLog<Record, 8> log(16);
  for (std::int64_t i = 0; i < 30; ++i) log.push(makeRecord(i));
  EXPECT_EQ(log.releaseBefore(20), 16u);  // whole chunks only: 0-7 and 8-15
  EXPECT_EQ(log.first(), 16u);
  EXPECT_EQ(log.size(), 30u);
  EXPECT_EQ(log[16].index, 16);
  std::int64_t expected = 16;
  log.forEach([&](const Record& r) { EXPECT_EQ(r.index, expected++); });
  EXPECT_EQ(expected, 30);
  EXPECT_EQ(log.releaseBefore(8), 16u);    // never backwards
  EXPECT_EQ(log.releaseBefore(100), 24u);  // never the chunk the writer is in
  for (std::int64_t i = 30; i < 40; ++i) log.push(makeRecord(i));
  EXPECT_EQ(log[39].twice, 78);
}

TEST(AppendOnlyLog, ReleasingOldChunksNeverDisturbsTheWriter) {
  constexpr std::int64_t kRecords = 200000;
  AppendOnlyLog<Record, 64> log(kRecords / 64 + 1);
  std::atomic<bool> done{false};
  std::atomic<std::int64_t> bad{0};
  std::thread releaser([&] {
    // Keeps the newest 1000 records, like MapStore's retirement (which also locks out readers).
    while (!done.load(std::memory_order_acquire)) {
      const std::size_t n = log.size();
      const std::size_t first = log.releaseBefore(n > 1000 ? n - 1000 : 0);
      if (first > n || (first > 0 && log[first].index != static_cast<std::int64_t>(first)))
        bad.fetch_add(1, std::memory_order_relaxed);
    }
  });
  for (std::int64_t i = 0; i < kRecords; ++i) log.push(makeRecord(i));
  done.store(true, std::memory_order_release);
  releaser.join();
  EXPECT_EQ(bad.load(), 0);
  ASSERT_EQ(log.size(), static_cast<std::size_t>(kRecords));
  EXPECT_EQ(log.releaseBefore(kRecords - 1000),
            static_cast<std::size_t>(kRecords - 1000) / 64 * 64);
  for (std::size_t i = log.first(); i < log.size(); ++i)
    EXPECT_EQ(log[i].index, static_cast<std::int64_t>(i));
}

}  // namespace
}  // namespace ldsm::concurrency
