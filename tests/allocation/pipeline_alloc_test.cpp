// The frame pipeline primitives (core/src/concurrency, core/src/pipeline/frame_pool.h) must not
// touch the heap after construction: a frame goes capture -> pool buffer -> ring -> tracking ->
// release for every camera frame.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "alloc_counter.h"
#include "concurrency/drop_oldest_ring.h"
#include "concurrency/latest_value.h"
#include "concurrency/parallel_tasks.h"
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

namespace ldsm::concurrency {
namespace {

TEST(PipelineAllocation, ParallelTasksRunWithoutAllocating) {
  // The window's linearisation and the tracing hand lambdas with several captures to run() once
  // per keyframe and per frame: no std::function, no heap.
  ParallelTasks tasks(2);
  std::vector<double> out(8, 0.0);
  const double a = 1.5, b = 2.5, c = 3.5;
  const test::AllocationScope scope;
  for (int round = 0; round < 200; ++round) {
    tasks.run(8, [&](int i) { out[static_cast<std::size_t>(i)] += a * i + b * round + c; });
  }
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_DOUBLE_EQ(out[3], 200 * (a * 3 + c) + b * 199 * 200 / 2);
}

}  // namespace
}  // namespace ldsm::concurrency
