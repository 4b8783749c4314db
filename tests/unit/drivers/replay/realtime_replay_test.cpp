// RealtimeReplaySource: frames are released at their own timestamps / speed on steady_clock,
// never earlier, and a slow consumer gets overdue frames at once (no skipping here).
#include "ldsm/drivers/realtime_replay_source.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <memory>
#include <thread>
#include <vector>

#include "ldsm/error.h"

namespace ldsm::drivers {
namespace {

using Clock = std::chrono::steady_clock;

/// Frames with the given timestamps (1x1 images).
class ListedSource : public FrameSource {
 public:
  explicit ListedSource(std::vector<double> timestamps) : timestamps_(std::move(timestamps)) {}
  SourceInfo info() const override {
    SourceInfo i;
    i.name = "list";
    i.width = 1;
    i.height = 1;
    i.frame_count = static_cast<std::int64_t>(timestamps_.size());
    i.nominal_fps = 20.0;
    return i;
  }
  bool next(Frame& f) override {
    if (next_ >= timestamps_.size()) return false;
    f.index = static_cast<std::int64_t>(next_);
    f.timestamp = timestamps_[next_++];
    f.image.resize(1, 1);
    return true;
  }

 private:
  std::vector<double> timestamps_;
  std::size_t next_ = 0;
};

double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

TEST(RealtimeReplay, RejectsBadSpeedAndNullSource) {
  EXPECT_THROW(RealtimeReplaySource(std::make_unique<ListedSource>(std::vector<double>{}), 0.0),
               ConfigError);
  EXPECT_THROW(RealtimeReplaySource(std::make_unique<ListedSource>(std::vector<double>{}), -1.0),
               ConfigError);
  EXPECT_THROW(
      RealtimeReplaySource(std::make_unique<ListedSource>(std::vector<double>{}), std::nan("")),
      ConfigError);
  EXPECT_THROW(RealtimeReplaySource(nullptr, 1.0), ConfigError);
}

TEST(RealtimeReplay, ReleasesEachFrameAtItsTimestampNeverEarlier) {
  // 50 ms apart, starting at an arbitrary time, played at 2x: one frame every 25 ms.
  std::vector<double> t;
  for (int i = 0; i < 8; ++i) t.push_back(100.0 + 0.05 * i);
  RealtimeReplaySource replay(std::make_unique<ListedSource>(t), 2.0);
  EXPECT_EQ(replay.info().name, "realtime:list");
  EXPECT_DOUBLE_EQ(replay.info().nominal_fps, 40.0);
  Frame frame;
  ASSERT_TRUE(replay.next(frame));
  const Clock::time_point start = Clock::now();
  for (int i = 1; i < 8; ++i) {
    ASSERT_TRUE(replay.next(frame));
    const double due = (t[static_cast<std::size_t>(i)] - t[0]) / 2.0;
    const double at = secondsSince(start);
    EXPECT_GE(at, due - 1e-4) << "frame " << i << " released early";  // start measured late
    EXPECT_LT(at, due + 0.2) << "frame " << i << " released far too late";
  }
  EXPECT_FALSE(replay.next(frame));
  const double total = secondsSince(start);
  EXPECT_GE(total, 0.175 - 1e-4);
}

TEST(RealtimeReplay, SlowConsumerGetsOverdueFramesAtOnceAndLatenessIsReported) {
  std::vector<double> t = {0.0, 0.01, 0.02, 0.03, 0.5};
  RealtimeReplaySource replay(std::make_unique<ListedSource>(t), 1.0);
  Frame frame;
  ASSERT_TRUE(replay.next(frame));
  const Clock::time_point start = Clock::now();
  std::this_thread::sleep_for(std::chrono::milliseconds(60));  // busy elsewhere: 3 frames due
  for (int i = 1; i <= 3; ++i) {
    ASSERT_TRUE(replay.next(frame));
    EXPECT_EQ(frame.index, i) << "nothing is skipped by the replay itself";
  }
  EXPECT_LT(secondsSince(start), 0.3) << "overdue frames must not wait";
  EXPECT_GT(replay.lastLatenessMs(), 20.0);
  ASSERT_TRUE(replay.next(frame));  // due at 0.5 s
  EXPECT_GE(secondsSince(start), 0.5 - 1e-4);
  EXPECT_LT(replay.lastLatenessMs(), 20.0);
  EXPECT_GT(replay.maxLatenessMs(), 20.0);
}

TEST(RealtimeReplay, TimestampsGoingBackwardsAreReleasedAtOnce) {
  RealtimeReplaySource replay(std::make_unique<ListedSource>(std::vector<double>{1.0, 0.5, 1.3}),
                              1.0);
  Frame frame;
  const Clock::time_point start = Clock::now();
  ASSERT_TRUE(replay.next(frame));
  ASSERT_TRUE(replay.next(frame));
  EXPECT_LT(secondsSince(start), 0.15);
  ASSERT_TRUE(replay.next(frame));
  EXPECT_GE(secondsSince(start), 0.3 - 1e-4);
}

}  // namespace
}  // namespace ldsm::drivers
