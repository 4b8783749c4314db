// LatestValue (triple buffer): latest-wins semantics single-threaded, and a concurrent writer
// and reader that must never observe a torn or older value.
#include "concurrency/latest_value.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <thread>

#include "ldsm/types.h"

namespace ldsm::concurrency {
namespace {

TEST(LatestValue, NothingBeforeTheFirstPublish) {
  LatestValue<int> latest;
  int out = -1;
  EXPECT_FALSE(latest.readLatest(out));
  EXPECT_FALSE(latest.readNew(out));
  EXPECT_EQ(out, -1);
}

TEST(LatestValue, ReaderSeesTheLastPublishedValue) {
  LatestValue<int> latest;
  latest.publish(1);
  latest.publish(2);
  latest.publish(3);
  int out = -1;
  EXPECT_TRUE(latest.readNew(out));
  EXPECT_EQ(out, 3);
  EXPECT_FALSE(latest.readNew(out));  // nothing newer
  out = -1;
  EXPECT_TRUE(latest.readLatest(out));  // still available
  EXPECT_EQ(out, 3);
  latest.publish(4);
  EXPECT_TRUE(latest.readNew(out));
  EXPECT_EQ(out, 4);
}

TEST(LatestValue, HoldsEigenPoses) {
  LatestValue<StampedPose> latest;
  StampedPose p;
  p.timestamp = 1.5;
  p.pose.translation = Eigen::Vector3d(1, 2, 3);
  p.pose.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  latest.publish(p);
  StampedPose out;
  ASSERT_TRUE(latest.readLatest(out));
  EXPECT_EQ(out.timestamp, 1.5);
  EXPECT_EQ(out.pose.translation, p.pose.translation);
  EXPECT_EQ(out.pose.rotation.coeffs(), p.pose.rotation.coeffs());
}

struct Triple {
  std::int64_t a = 0;
  std::int64_t b = 0;  // 2a
  std::int64_t c = 0;  // -a
};

TEST(LatestValue, ConcurrentReaderNeverSeesTornOrOlderValues) {
  constexpr std::int64_t kCount = 100000;
  LatestValue<Triple> latest;
  std::atomic<bool> done{false};
  std::thread writer([&] {
    for (std::int64_t i = 1; i <= kCount; ++i) latest.publish(Triple{i, 2 * i, -i});
    done.store(true, std::memory_order_release);
  });
  std::int64_t last = 0;
  std::int64_t reads = 0;
  std::int64_t torn = 0;
  std::int64_t older = 0;
  Triple t;
  for (;;) {
    const bool finished = done.load(std::memory_order_acquire);
    if (latest.readNew(t)) {
      ++reads;
      if (t.b != 2 * t.a || t.c != -t.a) ++torn;
      if (t.a <= last) ++older;
      last = t.a;
    } else if (finished) {
      break;  // everything was published before `done`: the last value has been read
    }
  }
  writer.join();
  EXPECT_EQ(torn, 0);
  EXPECT_EQ(older, 0);
  EXPECT_EQ(last, kCount);  // the final value is always delivered
  EXPECT_GE(reads, 1);
}

}  // namespace
}  // namespace ldsm::concurrency
