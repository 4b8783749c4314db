// Once the System runs, tracking a frame must not touch the heap. A synthetic corridor (320x240)
// goes through the System in deterministic mode; after a warm-up, the allocations made by
// submit() are counted for every frame that was tracked and did not become a keyframe (a
// keyframe is inserted into the window, which grows the map: that is mapping work and may
// allocate). In deterministic mode submit() covers the whole per-frame path: input checks,
// preprocessing (photometric correction, pyramid), coarse tracking, the trajectory record, the
// depth-filter update of the immature points (trace), the latest-pose triple buffer and the
// events.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "alloc_counter.h"
#include "ldsm/drivers/sim/sim_source.h"
#include "ldsm/system.h"

namespace ldsm {
namespace {

using test::AllocationScope;

class LastFrameListener : public SystemListener {
 public:
  void onFrame(const FrameEvent& e) override { last = e; }
  FrameEvent last;
};

TEST(SystemAllocation, TrackingNonKeyframesAllocatesNothingInSteadyState) {
  drivers::sim::SimOptions options;
  options.width = 320;
  options.height = 240;
  options.frames = 150;
  drivers::sim::SimSource source("forward", options);
  std::vector<drivers::Frame> frames(static_cast<std::size_t>(source.frameCount()));
  for (drivers::Frame& f : frames) ASSERT_TRUE(source.next(f));  // rendering allocates: first

  Config config;
  config.system.deterministic = true;
  System system(config, source.geometricCalibration(), source.photometricCalibration());
  LastFrameListener listener;
  system.setListener(&listener);

  // Warm-up: initialisation and the keyframes that fill the window. Until the window is full,
  // each keyframe brings more points to track and trace than any before it, and the buffers they
  // live in grow to their steady-state size; that is counted in keyframes, not frames, since
  // how many frames it takes depends on the keyframe rate.
  const int warm_up_keyframes = config.window.max_keyframes + 1;
  int keyframes_seen = 0;
  std::size_t measured = 0, allocations = 0;
  std::string offenders;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const drivers::Frame& f = frames[i];
    const AllocationScope scope;
    system.submit({f.image.view(), f.timestamp, f.exposure_ms});
    const std::size_t n = scope.count();
    if (listener.last.is_keyframe) ++keyframes_seen;
    if (keyframes_seen < warm_up_keyframes || !listener.last.has_pose || listener.last.is_keyframe)
      continue;
    ++measured;
    allocations += n;
    if (n > 0) offenders += " frame " + std::to_string(i) + ": " + std::to_string(n) + ";";
  }
  std::printf("%zu tracked non-keyframe frames measured, %zu allocations\n", measured, allocations);
  const SystemStats stats = system.stats();
  EXPECT_EQ(stats.tracking_losses, 0);
  EXPECT_GE(stats.keyframes, 5);
  // Most frames after the warm-up are ordinary tracked frames.
  EXPECT_GE(measured, 60u);
  EXPECT_EQ(allocations, 0u) << "allocations in" << offenders;
}

}  // namespace
}  // namespace ldsm
