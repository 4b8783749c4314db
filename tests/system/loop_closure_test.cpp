// End-to-end loop closure on rendered scenes. A perfect render hardly drifts, so the loop test
// gives the system a realistic defect: a focal length 2 % off the true one (as a badly calibrated
// camera would), which makes the odometry drift in scale and heading around the corridor loop.
// The same frames go to two systems, one with loop closure and one without.
#include <gtest/gtest.h>
#include <spdlog/spdlog.h>

#include <cstdlib>
#include <vector>

#include "ldsm/drivers/sim/sim_source.h"
#include "ldsm/eval/ate.h"
#include "ldsm/system.h"

namespace ldsm {
namespace {

class LoopListener : public SystemListener {
 public:
  void onLoopClosure(const LoopClosureEvent& e) override { loops.push_back(e); }
  std::vector<LoopClosureEvent> loops;
};

struct Run {
  explicit Run(const Config& config, const GeometricCalibration& g, const PhotometricCalibration& p)
      : system(config, g, p) {
    system.setListener(&listener);
  }
  System system;
  LoopListener listener;
};

Config deterministicConfig(bool loop) {
  Config c;
  c.system.deterministic = true;
  c.loop.enabled = loop;
  return c;
}

struct Outcome {
  eval::AteResult with_loop;
  eval::AteResult without_loop;
  SystemStats stats;
  std::vector<LoopClosureEvent> loops;
  std::size_t poses = 0;
  std::int64_t frames = 0;
};

Outcome runBoth(const std::string& scene, std::int64_t frames, double focal_error) {
  if (std::getenv("LDSM_DEBUG")) spdlog::set_level(spdlog::level::info);
  drivers::sim::SimOptions opt;
  opt.frames = frames;
  drivers::sim::SimSource source(scene, opt);
  GeometricCalibration told = source.geometricCalibration();
  told.input.fx *= 1.0 + focal_error;
  told.input.fy *= 1.0 + focal_error;
  Run on(deterministicConfig(true), told, source.photometricCalibration());
  Run off(deterministicConfig(false), told, source.photometricCalibration());
  drivers::Frame frame;
  Outcome o;
  while (source.next(frame)) {
    const FrameView in{frame.image.view(), frame.timestamp, frame.exposure_ms};
    on.system.submit(in);
    off.system.submit(in);
    ++o.frames;
  }
  on.system.finish();
  off.system.finish();
  const Trajectory t_on = on.system.trajectory();
  o.with_loop = eval::computeAte(source.groundTruth(), t_on);
  o.without_loop = eval::computeAte(source.groundTruth(), off.system.trajectory());
  o.stats = on.system.stats();
  o.loops = on.listener.loops;
  o.poses = t_on.size();
  std::printf(
      "%s (focal error %+.1f %%): %zu loops, ATE %.4f m with loop closure, %.4f m without "
      "(%.1f %%), path %.1f m\n",
      scene.c_str(), 100.0 * focal_error, o.loops.size(), o.with_loop.rmse, o.without_loop.rmse,
      100.0 * o.with_loop.rmse / o.without_loop.rmse, o.with_loop.gt_path_length);
  return o;
}

// Measured: 0.065 m with loop closure against 0.61 m without (10.6 %), 4 loops from keyframe
// ~338 on (the camera is back at the start after 54 s), Sim(3) scale ~1.27 (the scale drift).
// About 95 s (both systems are fed the same rendered frames).
TEST(LoopClosure, DriftingCorridorLoopIsClosedAndCutsTheError) {
  const Outcome o = runBoth("loop", 0, 0.02);
  EXPECT_EQ(o.stats.tracking_losses, 0);
  // Every tracked frame has a loop-corrected pose (plus the initializer's reference frame).
  EXPECT_GE(static_cast<std::int64_t>(o.poses), o.stats.tracked_frames);
  EXPECT_GE(static_cast<double>(o.poses), 0.99 * static_cast<double>(o.frames));
  ASSERT_FALSE(o.loops.empty()) << "no loop detected when the camera came back to the start";
  EXPECT_EQ(o.stats.loops.size(), o.loops.size());
  for (const LoopClosureEvent& e : o.loops) {
    EXPECT_GT(e.current_keyframe_id, e.matched_keyframe_id + 20);
    EXPECT_GE(e.inliers, Config{}.loop.min_inliers);
    EXPECT_GT(e.scale, 0.5);
    EXPECT_LT(e.scale, 2.0);
  }
  // The drift without loop closure must be visible for the test to mean anything.
  EXPECT_GT(o.without_loop.rmse, 0.004 * o.without_loop.gt_path_length);
  EXPECT_LE(o.with_loop.rmse, 0.3 * o.without_loop.rmse);
}

// Measured: no loop over the 54 m straight corridor (its repeating doors and posters included).
TEST(LoopClosure, ForwardCorridorNeverRevisitsAndFindsNoLoop) {
  const Outcome o = runBoth("forward", 0, 0.0);
  EXPECT_EQ(o.stats.tracking_losses, 0);
  EXPECT_TRUE(o.loops.empty()) << o.loops.size() << " false loop(s), first "
                               << o.loops.front().current_keyframe_id << " -> "
                               << o.loops.front().matched_keyframe_id;
  EXPECT_LE(o.with_loop.rmse, 1.5 * o.without_loop.rmse + 1e-3);
}

}  // namespace
}  // namespace ldsm
