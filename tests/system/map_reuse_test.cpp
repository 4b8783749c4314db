// End-to-end map reuse on rendered scenes with exact ground truth (docs/map-reuse.md): map
// keyframes come back into the window on a revisit and never on a forward corridor; a second lap
// of the same loop hardly adds to the map and is no less accurate than the first; after frames
// of noise, tracking resumes in the map it had (same frame and scale), without a new map.
#include <gtest/gtest.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "ldsm/drivers/dataset_calibration.h"
#include "ldsm/drivers/dataset_description.h"
#include "ldsm/drivers/dataset_source.h"
#include "ldsm/drivers/sim/sim_scene.h"
#include "ldsm/drivers/sim/sim_source.h"
#include "ldsm/drivers/trajectory_io.h"
#include "ldsm/eval/ate.h"
#include "ldsm/system.h"
#include "noise_image.h"
#include "real_sequence.h"
#include "test_paths.h"

namespace ldsm {
namespace {

class ReuseListener : public SystemListener {
 public:
  void onReuse(const ReuseEvent& e) override { reactivated += e.reactivated.size(); }
  void onTrackingLost(const TrackingLostEvent&) override { ++lost; }
  void onRelocalized(const RelocalizedEvent& e) override {
    ++relocalized;
    relocalizations.push_back(e);
  }
  std::vector<RelocalizedEvent> relocalizations;
  std::size_t reactivated = 0;
  int lost = 0;
  int relocalized = 0;
};

Config deterministicConfig(bool reuse) {
  Config c;
  c.system.deterministic = true;
  c.reuse.enabled = reuse;
  return c;
}

/// A frame of uniform noise (a camera glitch: nothing to track, nothing to initialise from).
struct SceneRun {
  std::int64_t frames = 0;   ///< 0: the scene's default length
  double mark_time = 1e300;  ///< stats are also taken when the frames reach this time
  std::int64_t noise_first = -1, noise_last = -1;  ///< frames replaced by noise
  bool black = false;  ///< ... by black frames instead (rejected as input: a gap in time)

  SystemStats stats, at_mark;
  Trajectory trajectory;
  eval::AteResult ate;
  ReuseListener listener;

  void run(const std::string& scene) {
    if (std::getenv("LDSM_DEBUG")) spdlog::set_level(spdlog::level::debug);
    drivers::sim::SimOptions opt;
    opt.frames = frames;
    drivers::sim::SimSource source(scene, opt);
    System system(deterministicConfig(true), source.geometricCalibration(),
                  source.photometricCalibration());
    system.setListener(&listener);
    drivers::Frame frame;
    bool marked = false;
    while (source.next(frame)) {
      if (!marked && frame.timestamp >= mark_time) {
        at_mark = system.stats();
        marked = true;
      }
      if (frame.index >= noise_first && frame.index <= noise_last) {
        if (black)
          frame.image.fill(0);
        else
          test::fillWithNoise(frame.image, static_cast<std::uint32_t>(frame.index));
      }
      system.submit({frame.image.view(), frame.timestamp, frame.exposure_ms});
    }
    system.finish();
    stats = system.stats();
    trajectory = system.trajectory();
    ate = eval::computeAte(source.groundTruth(), trajectory);
  }
  double rmseBetween(double first, double last) const {
    double sum = 0.0;
    int n = 0;
    for (std::size_t i = 0; i < ate.pairs.size(); ++i) {
      const double t = trajectory[ate.pairs[i].est].timestamp;
      if (t < first || t >= last) continue;
      sum += ate.errors[i] * ate.errors[i];
      ++n;
    }
    return n > 0 ? std::sqrt(sum / n) : NAN;
  }
};

TEST(MapReuse, ForwardCorridorReactivatesNothing) {
  SceneRun r;
  r.frames = 300;
  r.run("forward");
  const SystemStats& s = r.stats;
  EXPECT_GT(s.keyframes, 20);
  // Never a revisit: nothing comes back and nothing is redundant with the map.
  EXPECT_EQ(s.reuse.reactivations, 0);
  EXPECT_EQ(r.listener.reactivated, 0u);
  EXPECT_EQ(s.reuse.culled_keyframes, 0);
  // Every keyframe but the window's (not yet handed to the map) keeps its data.
  EXPECT_GE(s.map.data_keyframes, s.map.keyframes - 8);
}

// The map's budget (reuse.max_map_keyframes): however far the camera goes, at most that many
// keyframes keep their points and features; the others keep their poses, so the trajectory is
// whole and as accurate.
TEST(MapReuse, MapBudgetBoundsTheKeptKeyframes) {
  auto run = [](int budget) {
    drivers::sim::SimOptions opt;
    opt.frames = 300;
    drivers::sim::SimSource source("forward", opt);
    Config config = deterministicConfig(true);
    config.reuse.max_map_keyframes = budget;
    System system(config, source.geometricCalibration(), source.photometricCalibration());
    drivers::Frame frame;
    while (source.next(frame))
      system.submit({frame.image.view(), frame.timestamp, frame.exposure_ms});
    system.finish();
    return std::make_pair(system.stats(),
                          eval::computeAte(source.groundTruth(), system.trajectory()));
  };
  const auto [free, free_ate] = run(0);
  const auto [bounded, bounded_ate] = run(10);
  std::printf("budget: %lld kept of %lld (no budget: %lld), ATE %.4f m (%.4f)\n",
              static_cast<long long>(bounded.map.data_keyframes),
              static_cast<long long>(bounded.map.keyframes),
              static_cast<long long>(free.map.data_keyframes), bounded_ate.rmse, free_ate.rmse);
  ASSERT_GT(free.map.data_keyframes, 20) << "the run must make more keyframes than the budget";
  EXPECT_LE(bounded.map.data_keyframes, 10);
  EXPECT_EQ(bounded.map.keyframes, free.map.keyframes);
  EXPECT_LT(bounded.map.bytes, free.map.bytes / 2);
  // The forward corridor never comes back: what the budget drops is never needed again.
  EXPECT_EQ(bounded_ate.matched, free_ate.matched);
  EXPECT_LE(bounded_ate.rmse, free_ate.rmse * 1.05 + 1e-4);
}

// Measured (deterministic, this machine): lap 1 ATE 0.0236 m, lap 2 0.0232 m (one alignment),
// 324 keyframes kept after lap 1 and 329 after lap 2 of 701 made (with reuse.trial_check on:
// lap 2 0.0241 m, 8 map keyframes from the end of lap 1 turned down). `ldsm run` on the rendered
// scene: 0.020 m with reuse, 0.068 m with --no-reuse.
TEST(MapReuse, SecondLapOfALoopIsTrackedAgainstTheMapAndHardlyGrowsIt) {
  SceneRun r;
  const double lap = drivers::sim::makeSimScene("loop2").path.period();
  r.mark_time = lap;
  r.run("loop2");
  const SystemStats &s = r.stats, &lap1_stats = r.at_mark;
  const double lap1 = r.rmseBetween(0.0, lap), lap2 = r.rmseBetween(lap, 1e9);
  std::printf(
      "loop2: ATE %.4f m (lap 1 %.4f, lap 2 %.4f); keyframes kept %lld after lap 1, %lld after "
      "lap 2 (%lld made); %lld reactivations, %lld culled, %lld turned down by the trial\n",
      r.ate.rmse, lap1, lap2, static_cast<long long>(lap1_stats.map.data_keyframes),
      static_cast<long long>(s.map.data_keyframes), static_cast<long long>(s.map.keyframes),
      static_cast<long long>(s.reuse.reactivations),
      static_cast<long long>(s.reuse.culled_keyframes),
      static_cast<long long>(s.reuse.rejected_photometric));
  ASSERT_GT(lap1_stats.frames, 0);
  EXPECT_EQ(s.initializations, 1);
  EXPECT_GE(s.tracked_frames, s.frames - 10) << "all but the initialisation";
  // The second lap is tracked against the first lap's map ...
  EXPECT_GT(s.reuse.reactivations, 20);
  EXPECT_EQ(r.listener.reactivated, static_cast<std::size_t>(s.reuse.reactivations));
  EXPECT_GT(s.reuse.culled_keyframes, lap1_stats.map.data_keyframes / 2);
  // ... adds at most a tenth of the first lap's keyframes to it ...
  EXPECT_LE(s.map.data_keyframes - lap1_stats.map.data_keyframes,
            lap1_stats.map.data_keyframes / 10);
  // ... and is as accurate as the first lap (the same map; a small margin for other CPUs).
  EXPECT_LE(lap2, 1.1 * lap1);
  // Without reuse the second lap is a fresh copy that drifts on: 0.068 m.
  EXPECT_LT(r.ate.rmse, 0.035);
}

TEST(MapReuse, AfterNoiseTrackingResumesInTheOldMapFrame) {
  SceneRun r;
  r.frames = 700;
  r.noise_first = 400;
  r.noise_last = 414;
  r.run("loop");
  const SystemStats& s = r.stats;
  std::printf("noise: %lld lost, %lld relocalised (%lld attempts), %lld new maps, %zu poses\n",
              static_cast<long long>(s.tracking_losses),
              static_cast<long long>(s.reuse.relocalizations),
              static_cast<long long>(s.reuse.relocalization_attempts),
              static_cast<long long>(s.reuse.new_maps), r.trajectory.size());
  EXPECT_GE(r.listener.lost, 1);
  EXPECT_GE(s.reuse.relocalizations, 1);
  EXPECT_EQ(r.listener.relocalized, s.reuse.relocalizations);
  EXPECT_EQ(s.reuse.new_maps, 0);
  EXPECT_EQ(s.initializations, 1) << "relocalised, not re-initialised";
  // One trajectory in one frame: the poses after the noise continue the ones before, so a single
  // Sim(3) alignment fits both halves as well as the clean part alone.
  const double t_noise = 400 / drivers::sim::SimOptions{}.fps;
  const double before = r.rmseBetween(0.0, t_noise), after = r.rmseBetween(t_noise, 1e9);
  std::printf("noise: ATE %.4f m (before %.4f, after %.4f)\n", r.ate.rmse, before, after);
  EXPECT_GT(r.ate.matched, 700u - 2 * 15u);
  // The bar is twice the ATE of the same 700 frames without noise, run here: a figure
  // written down goes stale with the engine and the machine (it said 0.0024 m, measured when
  // this test was written; at 6253d0b on an AMD EPYC the clean run is 0.0036 m, the run with
  // noise 0.0049 m: 0.0043 before it and 0.0056 after).
  SceneRun clean;
  clean.frames = 700;
  clean.run("loop");
  std::printf("clean: ATE %.4f m\n", clean.ate.rmse);
  EXPECT_LT(r.ate.rmse, 2.0 * clean.ate.rmse);
  EXPECT_LT(after, 2.0 * clean.ate.rmse);
}

// sim:loop's 700 frames with frames first..last black (refused as input: a gap in time).
SceneRun runWithBlackGap(std::int64_t first, std::int64_t last) {
  SceneRun r;
  r.frames = 700;
  r.noise_first = first;
  r.noise_last = last;
  r.black = true;
  r.run("loop");
  return r;
}

struct GapErrors {
  double before = 0.0, after = 0.0;  ///< ATE of the poses before and after the gap, one alignment
};

// The gap from frame `first` was one loss, found again in the same map: no new map, no second
// initialisation. Returns the errors before and after it.
GapErrors expectOneLossFoundInTheSameMap(const SceneRun& r, std::int64_t first,
                                         std::int64_t gap_frames, const char* label) {
  const SystemStats& s = r.stats;
  std::printf("%s: %lld rejected, %lld lost, %lld relocalised, %lld new maps, %zu poses\n", label,
              static_cast<long long>(s.rejected_frames), static_cast<long long>(s.tracking_losses),
              static_cast<long long>(s.reuse.relocalizations),
              static_cast<long long>(s.reuse.new_maps), r.trajectory.size());
  EXPECT_EQ(s.rejected_frames, gap_frames);
  EXPECT_EQ(r.listener.lost, 1) << "the gap counts as a loss";
  EXPECT_EQ(s.reuse.relocalizations, 1);
  EXPECT_EQ(s.reuse.new_maps, 0);
  EXPECT_EQ(s.initializations, 1);
  const double t_gap = static_cast<double>(first) / drivers::sim::SimOptions{}.fps;
  const GapErrors e{r.rmseBetween(0.0, t_gap), r.rmseBetween(t_gap, 1e9)};
  std::printf("%s: ATE %.4f m (before %.4f, after %.4f)\n", label, r.ate.rmse, e.before, e.after);
  return e;
}

// Black frames are refused as input, so the frame after them comes 0.5 s after the last one
// tracked: farther than the motion model reaches. It is looked for as after a loss (map
// relocalisation, then the window's wide search from the last pose) and must fit as well as
// before; tracked as an ordinary frame, it found a pose that fitted well enough for that and the
// map went wrong from there (vamr_desk_loop, frames 350-389 black: ATE 0.0356 m against 0.0007).
TEST(MapReuse, AfterAGapOfBlackFramesTrackingResumesInTheOldMapFrame) {
  const SceneRun r = runWithBlackGap(400, 414);
  // One trajectory in one frame: under one Sim(3) alignment the poses after the gap are as good
  // as the ones before it (measured: 0.0041 m before, 0.0042 m after; the clean run 0.0036 m,
  // which AfterNoiseTrackingResumesInTheOldMapFrame runs: not again here).
  const GapErrors e = expectOneLossFoundInTheSameMap(r, 400, 15, "black");
  EXPECT_GT(r.ate.matched, 700u - 2 * 15u);
  EXPECT_LT(e.after, 2.0 * e.before);
  EXPECT_LT(r.ate.rmse, 2.0 * e.before);
}

// Two seconds without images while the camera drives on (frames 400-459 black: 1.9 m down the
// rendered corridor, 5.7 degrees of turn): no rotated guess around the last pose reaches that
// far, and the map has no keyframe there yet. The frame after the gap is tracked against the
// kept window from the last motion's translation continued over the gap (with the wide search's
// rotations), and resumes with more of its residual than after a short gap (the view changed:
// 2.3-2.8 times the residual before the loss, 93-96 % inliers). Without that, relocalisation
// failed for 5 s, a new map started that never met the old one, and the trajectory was in two
// frames (ATE 1.30 m). About 40 s.
TEST(MapReuse, AfterTwoSecondsWithoutImagesADrivingCameraResumesWhereItDroveTo) {
  const SceneRun r = runWithBlackGap(400, 459);
  const GapErrors e = expectOneLossFoundInTheSameMap(r, 400, 60, "2 s black");
  EXPECT_GT(r.ate.matched, 700u - 60u - 10u);
  // The bar: twice the ATE of the same 700 frames without the gap, run here (measured
  // 0.0036 m; with the gap 0.0040 m, 0.0028 before it and 0.0055 after it under one alignment).
  SceneRun clean;
  clean.frames = 700;
  clean.run("loop");
  std::printf("clean: ATE %.4f m\n", clean.ate.rmse);
  EXPECT_LT(r.ate.rmse, 2.0 * clean.ate.rmse);
  EXPECT_LT(e.after, 2.0 * clean.ate.rmse);
}

/// vamr_desk_loop's first `frames` frames, deterministic with the defaults, those in [first, end)
/// black.
struct DeskGapRun {
  SystemStats stats;
  int lost = 0;
  eval::AteResult ate;
  std::size_t after_gap = 0;  ///< poses of frames after the gap
};

DeskGapRun runDeskWithBlackFrames(const std::string& folder, std::int64_t first, std::int64_t end,
                                  std::int64_t frames) {
  if (std::getenv("LDSM_DEBUG")) spdlog::set_level(spdlog::level::debug);
  const test::RealSequence seq = test::openRealSequence(folder);
  System system(deterministicConfig(true), seq.calibration.geometric, seq.calibration.photometric);
  ReuseListener listener;
  system.setListener(&listener);
  drivers::Frame frame;
  while (seq.source->next(frame) && frame.index < frames) {
    if (frame.index >= first && frame.index < end) frame.image.fill(0);
    system.submit({frame.image.view(), frame.timestamp, frame.exposure_ms});
  }
  system.finish();
  DeskGapRun r;
  r.stats = system.stats();
  r.lost = listener.lost;
  const Trajectory trajectory = system.trajectory();
  r.ate = eval::computeAte(seq.ground_truth, trajectory);
  const double gap_end = seq.description.timestamps[static_cast<std::size_t>(end)];
  for (const StampedPose& p : trajectory) r.after_gap += p.timestamp >= gap_end ? 1 : 0;
  std::printf(
      "vamr, frames %lld-%lld black: %lld lost, %lld relocalised, %lld new maps, ATE %.5f m over "
      "%zu poses (%zu after the gap)\n",
      static_cast<long long>(first), static_cast<long long>(end - 1),
      static_cast<long long>(r.stats.tracking_losses),
      static_cast<long long>(r.stats.reuse.relocalizations),
      static_cast<long long>(r.stats.reuse.new_maps), r.ate.rmse, r.ate.matched, r.after_gap);
  return r;
}

// The same on the real hand-held desk sequence, whose camera moves unevenly: frames 350-389
// (1.3 s) black, the first 450 frames. Tracked as an ordinary frame after the gap, frame 390 found
// a pose 3.6 cm off that passed as tracked, and the map went wrong from there (the whole sequence:
// ATE 0.0356 m; clean 0.00075 m). Looked for as after a loss, it resumes in the window (the wide
// search: the camera moved 4.6 cm and turned 6 degrees meanwhile): 0.0007 m. The bar is twice the
// clean run's on DSO's figure for the sequence (0.0008-0.0009 m), for other CPUs. About 15 s.
TEST(MapReuse, VamrDeskLoopResumesInItsMapAfterFortyBlackFrames) {
  const std::string folder = test::sharedData("vamr_desk_loop");
  if (folder.empty())
    GTEST_SKIP() << "../shared/data/vamr_desk_loop is absent: real-data test skipped";
  const DeskGapRun r = runDeskWithBlackFrames(folder, 350, 390, 450);
  EXPECT_EQ(r.stats.rejected_frames, 40);
  EXPECT_EQ(r.lost, 1);
  EXPECT_EQ(r.stats.reuse.relocalizations, 1);
  EXPECT_EQ(r.stats.reuse.new_maps, 0);
  EXPECT_GT(r.ate.matched, 450u - 40u - 20u);
  EXPECT_LT(r.ate.rmse, 2.0 * 0.0009);
}

// Frames 360-399 black: the window's track of the frames after the gap is right (0.3-1.1 mm from
// the clean run's poses) but fits at 63-68 % inliers, short of the 70 % a single frame needs, and
// the map finds none of them (PnP 0-7 inliers of 16-22 ORB matches). It resumes once that fit has
// held for five frames in a row (TrackingStage::kSteadyFits). Without that no frame was found in
// the 5 s before a new map started (the whole sequence: ATE 0.035 m, two maps never merged), and
// in this test's 460 frames no frame after the gap had a pose. About 15 s.
TEST(MapReuse, VamrDeskLoopResumesWhereOnlyTheWindowsTrackHoldsAfterTheGap) {
  const std::string folder = test::sharedData("vamr_desk_loop");
  if (folder.empty())
    GTEST_SKIP() << "../shared/data/vamr_desk_loop is absent: real-data test skipped";
  const DeskGapRun r = runDeskWithBlackFrames(folder, 360, 400, 460);
  EXPECT_EQ(r.lost, 1);
  EXPECT_EQ(r.stats.reuse.relocalizations, 1);
  EXPECT_EQ(r.stats.reuse.new_maps, 0);
  // Resumed within the first frames after the gap (five attempts, and a few more for other CPUs).
  EXPECT_GE(r.after_gap, 60u - 10u);
  EXPECT_LT(r.ate.rmse, 2.0 * 0.0009);
}

// Frames 300-379 black (2.7 s): the camera is 1.3 cm from where it was at frame 115, but ORB finds
// 23 matches with a depth to the map keyframes there, mostly wrong on the checkerboard, and PnP
// fits 8-14 of them: it never found the frame, and after reuse.relocalization_timeout_s a new map
// started that no loop ever merged (the whole sequence: ATE 0.039 m). The direct fit from the
// candidate keyframe's own pose finds the first frame after the gap (the whole sequence: 0.0008 m,
// as in the clean run). About 10 s.
TEST(MapReuse, VamrDeskLoopIsFoundInItsMapAfterEightyBlackFramesWherePnpFails) {
  const std::string folder = test::sharedData("vamr_desk_loop");
  if (folder.empty())
    GTEST_SKIP() << "../shared/data/vamr_desk_loop is absent: real-data test skipped";
  const DeskGapRun r = runDeskWithBlackFrames(folder, 300, 380, 440);
  EXPECT_EQ(r.stats.rejected_frames, 80);
  EXPECT_EQ(r.lost, 1);
  EXPECT_EQ(r.stats.reuse.relocalizations, 1);
  EXPECT_EQ(r.stats.reuse.new_maps, 0);
  // Found within the first frames after the gap (at the first here; a few more for other CPUs).
  EXPECT_GE(r.after_gap, 60u - 10u);
  EXPECT_LT(r.ate.rmse, 2.0 * 0.0009);
}

// Frames 200-239 black: the camera moves 15 cm meanwhile and is found 70 frames after the gap. At
// frames 424-428 it jerks (8 mm and 1.25 degrees a frame), and the frames after the keyframe there
// fitted their new reference at 72 % inliers, sliding to 46 % and 3.6 cm off by frame 443, with no
// keyframe and no loss (the first 500 frames: ATE 0.0126 m). A frame that fits with fewer than
// keyframes.min_inlier_fraction (70 %) inliers makes a keyframe: 0.0012 m. About 10 s.
TEST(MapReuse, VamrDeskLoopAfterAGapMakesAKeyframeWhereTheFitLosesItsInliers) {
  const std::string folder = test::sharedData("vamr_desk_loop");
  if (folder.empty())
    GTEST_SKIP() << "../shared/data/vamr_desk_loop is absent: real-data test skipped";
  const DeskGapRun r = runDeskWithBlackFrames(folder, 200, 240, 500);
  EXPECT_EQ(r.stats.reuse.relocalizations, 1);
  EXPECT_EQ(r.stats.reuse.new_maps, 0);
  EXPECT_LT(r.ate.rmse, 2.0 * 0.0009);
}

class MergeListener : public ReuseListener {
 public:
  void onMapsMerged(const MapMergeEvent& e) override { merges.push_back(e); }
  std::vector<MapMergeEvent> merges;
};

/// Ground truth of the frames as fed (re-stamped frames take the pose of the frame they show).
void addTruth(const Trajectory& gt, std::int64_t index, double timestamp, Trajectory& out) {
  StampedPose p = gt[static_cast<std::size_t>(index)];
  p.timestamp = timestamp;
  out.push_back(p);
}

// A loss longer than reuse.relocalization_timeout_s in the middle of the corridor loop: a second
// map starts in unmapped territory, its poses are reported as map 1 (their own frame); when the
// camera is back at the start, a loop connects the two maps, the first is moved into the second
// one's frame, and every pose is reported in the first map's frame again.
TEST(MapReuse, MapStartedAfterALongLossIsMergedIntoTheFirstMap) {
  if (std::getenv("LDSM_DEBUG")) spdlog::set_level(spdlog::level::debug);
  drivers::sim::SimSource source("loop", drivers::sim::SimOptions{});
  Config config = deterministicConfig(true);
  config.reuse.relocalization_timeout_s = 0.1;
  System system(config, source.geometricCalibration(), source.photometricCalibration());
  MergeListener listener;
  system.setListener(&listener);
  drivers::Frame frame;
  const std::int64_t noise_first = 400, noise_last = 429;
  bool saw_second_map = false;
  while (source.next(frame)) {
    if (frame.index >= noise_first && frame.index <= noise_last)
      test::fillWithNoise(frame.image, static_cast<std::uint32_t>(frame.index));
    system.submit({frame.image.view(), frame.timestamp, frame.exposure_ms});
    if (frame.index == 900) {
      // Before the camera is back: the second map's poses are labelled as such.
      for (const StampedPose& p : system.trajectory()) saw_second_map |= p.map == 1;
    }
  }
  system.finish();
  const SystemStats s = system.stats();
  const Trajectory trajectory = system.trajectory();
  const eval::AteResult ate = eval::computeAte(source.groundTruth(), trajectory);
  std::printf("merge: %lld new maps, %lld merges, %lld loops, ATE %.4f m over %zu poses\n",
              static_cast<long long>(s.reuse.new_maps), static_cast<long long>(s.reuse.merges),
              static_cast<long long>(s.loops.size()), ate.rmse, trajectory.size());
  EXPECT_EQ(s.reuse.new_maps, 1);
  EXPECT_TRUE(saw_second_map) << "poses of the second map must say so before the merge";
  ASSERT_EQ(listener.merges.size(), 1u);
  EXPECT_EQ(s.reuse.merges, 1);
  const MapMergeEvent& m = listener.merges.front();
  EXPECT_EQ(m.merged_map, 0);
  EXPECT_EQ(m.into_map, 1);
  EXPECT_TRUE(m.in_map_frame);
  EXPECT_GT(m.moved_keyframes, 10);
  // One trajectory in one frame: every pose in the first map's frame, and one Sim(3) fits all.
  for (const StampedPose& p : trajectory) ASSERT_EQ(p.map, 0) << "at t = " << p.timestamp;
  EXPECT_GT(ate.matched, trajectory.size() - 10);
  // Both maps drift on their own (no odometry connects them; the corridor loop's single-map drift
  // without loop closure is 0.32 m over the lap, LoopClosure.DriftingCorridorLoop...): a merge
  // that put the second map in the wrong place or scale would be metres off.
  EXPECT_LT(ate.rmse, 0.2);
}

// A camera carried somewhere else while tracking is lost (kidnapped) is found by place
// recognition (the loop closer's bag of words) anywhere in the map, not only near its last pose:
// 700 frames of the corridor loop, 10 frames of noise, then the camera is back at frame 150's
// place, 11 m away. Measured: found in map keyframe 27 at the first clean frame, ATE 0.0027 m
// over both segments; searching only the reuse.relocalization_near_candidates (24) keyframes
// nearest to the last pose and the last window's covisible map, it is not found before the
// timeout starts a new map. (Before the near search was capped it reached all of this small
// map: three median depths of the corridor span it.)
TEST(MapReuse, KidnappedCameraIsFoundAnywhereInTheMap) {
  struct Outcome {
    SystemStats stats;
    eval::AteResult ate;
    std::vector<RelocalizedEvent> relocalizations;
  };
  const std::int64_t first_clean = 710;  // the first frame after the noise
  if (std::getenv("LDSM_DEBUG")) spdlog::set_level(spdlog::level::debug);
  auto run = [&](int place_candidates) {
    drivers::sim::SimSource source("loop", drivers::sim::SimOptions{});
    Config config = deterministicConfig(true);
    config.reuse.relocalization_place_candidates = place_candidates;
    System system(config, source.geometricCalibration(), source.photometricCalibration());
    ReuseListener listener;
    system.setListener(&listener);
    drivers::Frame frame;
    Trajectory truth;
    double t = 0.0;
    const double dt = 1.0 / drivers::sim::SimOptions{}.fps;
    auto feed = [&](drivers::Frame& f, bool noise) {
      if (noise) test::fillWithNoise(f.image, static_cast<std::uint32_t>(f.index + 7919));
      system.submit({f.image.view(), t, f.exposure_ms});
      if (!noise) addTruth(source.groundTruth(), f.index, t, truth);
      t += dt;
    };
    while (source.next(frame) && frame.index < 700) feed(frame, false);
    for (int k = 0; k < 10; ++k) feed(frame, true);
    source.seek(150);
    while (source.next(frame) && frame.index < 450) feed(frame, false);
    system.finish();
    Outcome o;
    o.stats = system.stats();
    o.ate = eval::computeAte(truth, system.trajectory());
    o.relocalizations = listener.relocalizations;
    return o;
  };
  const Outcome with = run(Config{}.reuse.relocalization_place_candidates);
  const Outcome without = run(0);
  auto found_at = [](const Outcome& o) {
    return o.relocalizations.empty() ? std::int64_t{-1} : o.relocalizations.front().frame_index;
  };
  std::printf(
      "kidnapped: place recognition: found at frame %lld in map keyframe %d, %lld new maps, "
      "ATE %.4f m; near the last pose only: found at frame %lld\n",
      static_cast<long long>(found_at(with)),
      with.relocalizations.empty() ? -1 : with.relocalizations.front().map_keyframe_id,
      static_cast<long long>(with.stats.reuse.new_maps), with.ate.rmse,
      static_cast<long long>(found_at(without)));
  ASSERT_EQ(with.relocalizations.size(), 1u);
  EXPECT_LE(found_at(with), first_clean + 2) << "place recognition finds it at once";
  EXPECT_TRUE(found_at(without) < 0 || found_at(without) > found_at(with));
  EXPECT_EQ(with.stats.reuse.new_maps, 0);
  EXPECT_EQ(with.stats.initializations, 1) << "relocalised, not re-initialised";
  // One frame for both segments: a single Sim(3) fits them (clean 700 frames: 0.0024 m).
  EXPECT_GT(with.ate.matched, 990u);
  EXPECT_LT(with.ate.rmse, 2.0 * 0.0024);
}

}  // namespace
}  // namespace ldsm
