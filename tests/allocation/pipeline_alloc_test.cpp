// The frame pipeline primitives (core/src/concurrency, core/src/pipeline/frame_pool.h) must not
// touch the heap after construction: a frame goes capture -> pool buffer -> ring -> tracking ->
// release for every camera frame.
#include <gtest/gtest.h>

#include <cstdint>

#include "alloc_counter.h"
#include "concurrency/drop_oldest_ring.h"
#include "concurrency/latest_value.h"
#include "concurrency/spsc_ring.h"
#include "ldsm/types.h"
#include "pipeline/frame_pool.h"

namespace ldsm::pipeline {
namespace {

using concurrency::DropOldestRing;
using concurrency::LatestValue;
using concurrency::SpscRing;
using test::AllocationScope;

TEST(PipelineAllocation, SteadyStateFrameFlowAllocatesNothing) {
  FramePool pool(6, 320, 240);
  DropOldestRing<FrameTicket> live(4);
  SpscRing<FrameTicket> offline(4);
  LatestValue<StampedPose> latest_pose;

  const AllocationScope scope;
  for (std::int64_t i = 0; i < 1000; ++i) {
    FrameTicket ticket;
    ticket.buffer = pool.tryAcquire();
    ASSERT_GE(ticket.buffer, 0);
    ticket.index = i;
    pool.image(ticket.buffer).resize(320, 240);
    pool.image(ticket.buffer).fill(static_cast<std::uint8_t>(i));
    FrameTicket old;
    if (live.pushDroppingOldest(ticket, old)) pool.release(old.buffer);  // full most of the time
    if (i % 3 == 0 && live.tryPop(ticket)) {
      ASSERT_TRUE(offline.tryPush(ticket));
      ASSERT_TRUE(offline.tryPop(ticket));
      StampedPose pose;
      pose.timestamp = static_cast<double>(ticket.index);
      latest_pose.publish(pose);
      pool.release(ticket.buffer);
    }
    StampedPose seen;
    latest_pose.readLatest(seen);
  }
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_GT(live.droppedCount(), 0u);
}

}  // namespace
}  // namespace ldsm::pipeline
