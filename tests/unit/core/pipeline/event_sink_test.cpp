// EventSink: every loop event reaches the listener, the statistics keep only the newest
// SystemStats::kMaxLoopEvents of them (a long run closes a loop every few seconds) and count all.
#include "pipeline/event_sink.h"

#include <gtest/gtest.h>

namespace ldsm {
namespace {

struct CountingListener : SystemListener {
  int loops = 0;
  void onLoopClosure(const LoopClosureEvent&) override { ++loops; }
};

TEST(EventSink, KeepsTheNewestLoopEventsAndCountsThemAll) {
  EventSink sink;
  CountingListener listener;
  sink.setListener(&listener);
  const int n = SystemStats::kMaxLoopEvents + 6;
  for (int i = 0; i < n; ++i) {
    LoopClosureEvent e;
    e.current_keyframe_id = i;
    sink.loopClosed(e);
  }
  EXPECT_EQ(listener.loops, n);
  EXPECT_EQ(sink.loopsClosed(), n);
  const std::vector<LoopClosureEvent> kept = sink.loops();
  ASSERT_EQ(kept.size(), static_cast<std::size_t>(SystemStats::kMaxLoopEvents));
  EXPECT_EQ(kept.front().current_keyframe_id, 6);
  EXPECT_EQ(kept.back().current_keyframe_id, n - 1);
}

}  // namespace
}  // namespace ldsm
