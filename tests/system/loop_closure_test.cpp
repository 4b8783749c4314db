// End-to-end loop closure on rendered scenes. A perfect render hardly drifts, so the loop test
// gives the system a realistic defect: a focal length 2 % off the true one (as a badly calibrated
// camera would), which makes the odometry drift in scale and heading around the corridor loop.
// The same frames go to two systems, one with loop closure and one without.
#include <gtest/gtest.h>
#include <spdlog/spdlog.h>

#include <cstdlib>
#include <vector>

#include "ldsm/drivers/dataset_calibration.h"
#include "ldsm/drivers/dataset_description.h"
#include "ldsm/drivers/dataset_source.h"
#include "ldsm/drivers/sim/sim_source.h"
#include "ldsm/drivers/trajectory_io.h"
#include "ldsm/eval/ate.h"
#include "ldsm/system.h"
#include "real_sequence.h"
#include "test_paths.h"

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

Config deterministicConfig(bool loop, bool refine_focal) {
  Config c;
  c.system.deterministic = true;
  c.loop.enabled = loop;
  c.calibration.refine_focal = refine_focal;
  return c;
}

struct Outcome {
  Trajectory with_loop;
  Trajectory without_loop;
  eval::AteResult ate_with;
  eval::AteResult ate_without;
  SystemStats stats;
  std::vector<LoopClosureEvent> loops;
  std::int64_t frames = 0;

  void evaluate(const Trajectory& ground_truth) {
    ate_with = eval::computeAte(ground_truth, with_loop);
    ate_without = eval::computeAte(ground_truth, without_loop);
  }
};

/// `refine_focal`: false where a focal error is what makes the odometry drift (the refinement
/// would otherwise repair it: the corridor told +2 % drifts 0.036 m with it, 0.32 m without).
Outcome runBothOn(drivers::FrameSource& source, const GeometricCalibration& calibration,
                  const PhotometricCalibration& photometric, bool refine_focal = true) {
  if (std::getenv("LDSM_DEBUG")) spdlog::set_level(spdlog::level::info);
  Run on(deterministicConfig(true, refine_focal), calibration, photometric);
  Run off(deterministicConfig(false, refine_focal), calibration, photometric);
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
  o.with_loop = on.system.trajectory();
  o.without_loop = off.system.trajectory();
  o.stats = on.system.stats();
  o.loops = on.listener.loops;
  return o;
}

Outcome runBoth(const std::string& scene, std::int64_t frames, double focal_error) {
  drivers::sim::SimOptions opt;
  opt.frames = frames;
  drivers::sim::SimSource source(scene, opt);
  GeometricCalibration told = source.geometricCalibration();
  told.input.fx *= 1.0 + focal_error;
  told.input.fy *= 1.0 + focal_error;
  Outcome o = runBothOn(source, told, source.photometricCalibration(), focal_error == 0.0);
  o.evaluate(source.groundTruth());
  std::printf(
      "%s (focal error %+.1f %%): %zu loops, ATE %.4f m with loop closure, %.4f m without "
      "(%.1f %%), path %.1f m\n",
      scene.c_str(), 100.0 * focal_error, o.loops.size(), o.ate_with.rmse, o.ate_without.rmse,
      100.0 * o.ate_with.rmse / o.ate_without.rmse, o.ate_with.gt_path_length);
  return o;
}

// Measured: 0.047 m with loop closure against 0.32 m without (14.8 %), 23 loops from keyframe
// ~328 on (the camera is back at the start after 54 s), Sim(3) scale ~1.29 (the scale drift). The
// first loop disagrees with the drifted trajectory by chi2 ~137 under the loop's and the odometry
// chain's uncertainty together (the drift model allows ~4 % of scale over the 300 keyframes; the
// loop shows 29 %) and corrects it; most later ones agree with the corrected trajectory within
// that accuracy (chi2 < 18.5) and move nothing. About 95 s (both systems get the same frames).
TEST(LoopClosure, DriftingCorridorLoopIsClosedAndCutsTheError) {
  const Outcome o = runBoth("loop", 0, 0.02);
  EXPECT_EQ(o.stats.tracking_losses, 0);
  // Every tracked frame has a loop-corrected pose (plus the initializer's reference frame).
  EXPECT_GE(static_cast<std::int64_t>(o.with_loop.size()), o.stats.tracked_frames);
  EXPECT_GE(static_cast<double>(o.with_loop.size()), 0.99 * static_cast<double>(o.frames));
  ASSERT_FALSE(o.loops.empty()) << "no loop detected when the camera came back to the start";
  EXPECT_EQ(o.stats.loops.size(), o.loops.size());
  for (const LoopClosureEvent& e : o.loops) {
    EXPECT_GT(e.current_keyframe_id, e.matched_keyframe_id + 20);
    EXPECT_GE(e.inliers, Config{}.loop.min_inliers);
    EXPECT_GT(e.scale, 0.5);
    EXPECT_LT(e.scale, 2.0);
    EXPECT_EQ(e.corrected_keyframes > 0, e.drift_chi2 >= Config{}.loop.correction_chi2)
        << "loop " << e.current_keyframe_id << " -> " << e.matched_keyframe_id << ", chi2 "
        << e.drift_chi2;
  }
  // The first loop sees the whole drift (about 29 % in scale), far beyond what the odometry's
  // drift model allows, and corrects the trajectory.
  EXPECT_GT(o.loops.front().drift_chi2, 5.0 * Config{}.loop.correction_chi2);
  EXPECT_GT(o.loops.front().corrected_keyframes, 100);
  // The drift without loop closure must be visible for the test to mean anything.
  EXPECT_GT(o.ate_without.rmse, 0.004 * o.ate_without.gt_path_length);
  EXPECT_LE(o.ate_with.rmse, 0.3 * o.ate_without.rmse);
}

// Measured: no loop over the 54 m straight corridor (its repeating doors and posters included).
TEST(LoopClosure, ForwardCorridorNeverRevisitsAndFindsNoLoop) {
  const Outcome o = runBoth("forward", 0, 0.0);
  EXPECT_EQ(o.stats.tracking_losses, 0);
  EXPECT_TRUE(o.loops.empty()) << o.loops.size() << " false loop(s), first "
                               << o.loops.front().current_keyframe_id << " -> "
                               << o.loops.front().matched_keyframe_id;
  EXPECT_LE(o.ate_with.rmse, 1.5 * o.ate_without.rmse + 1e-3);
}

// The real hand-held desk sequence (../shared/data/vamr_desk_loop): the camera comes back to its
// start and over earlier views many times. Its odometry hardly drifts (ATE about 0.9 mm over
// 2.4 m), less than a loop measurement can resolve: the loops must be found, and closing them must
// not make the trajectory worse. Compared with the ground truth, the loops' measured Sim(3)s are
// off by 2-6 mrad and up to 2 % in scale, the odometry's relative poses by 1-2 mrad: correcting
// with them would make the trajectory worse (0.0011-0.0014 m). Measured: 6 loops (20-26 inliers,
// scale 0.98-1.00, chi2 0.3-2.3 under the loop's and the chain's uncertainty: none
// significant), ATE 0.00094 m with and without loop closure. About 30 s.
TEST(LoopClosure, VamrDeskLoopFindsItsLoopsAndKeepsItsAccuracy) {
  const std::string folder = test::sharedData("vamr_desk_loop");
  if (folder.empty())
    GTEST_SKIP() << "../shared/data/vamr_desk_loop is absent: real-data test skipped";
  const test::RealSequence seq = test::openRealSequence(folder);
  Outcome o = runBothOn(*seq.source, seq.calibration.geometric, seq.calibration.photometric);
  o.evaluate(seq.ground_truth);
  std::printf("vamr_desk_loop: %zu loops, ATE %.5f m with loop closure, %.5f m without\n",
              o.loops.size(), o.ate_with.rmse, o.ate_without.rmse);
  EXPECT_EQ(o.stats.tracking_losses, 0);
  EXPECT_GE(o.loops.size(), 2u) << "the camera comes back to earlier views many times";
  for (const LoopClosureEvent& e : o.loops) {
    EXPECT_GT(e.current_keyframe_id, e.matched_keyframe_id + 20);
    EXPECT_NEAR(e.scale, 1.0, 0.05) << "an odometry this accurate has no scale drift to find";
  }
  EXPECT_LE(o.ate_with.rmse, 1.05 * o.ate_without.rmse + 2e-5);
  EXPECT_LT(o.ate_with.rmse, 0.0010);  // the odometry target of the sequence
}

}  // namespace
}  // namespace ldsm
