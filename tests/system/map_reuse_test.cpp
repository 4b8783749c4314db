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
#include <vector>

#include "ldsm/drivers/sim/sim_scene.h"
#include "ldsm/drivers/sim/sim_source.h"
#include "ldsm/eval/ate.h"
#include "ldsm/system.h"

namespace ldsm {
namespace {

class ReuseListener : public SystemListener {
 public:
  void onReuse(const ReuseEvent& e) override { reactivated += e.reactivated.size(); }
  void onTrackingLost(const TrackingLostEvent&) override { ++lost; }
  void onRelocalized(const RelocalizedEvent&) override { ++relocalized; }
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
void fillWithNoise(ImageU8& image, std::uint32_t seed) {
  std::uint32_t x = seed * 2654435761u + 1u;
  for (int y = 0; y < image.height(); ++y)
    for (int u = 0; u < image.width(); ++u) {
      x = x * 1664525u + 1013904223u;
      image(u, y) = static_cast<std::uint8_t>(x >> 24);
    }
}

struct SceneRun {
  std::int64_t frames = 0;   ///< 0: the scene's default length
  double mark_time = 1e300;  ///< stats are also taken when the frames reach this time
  std::int64_t noise_first = -1, noise_last = -1;  ///< frames replaced by noise

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
      if (frame.index >= noise_first && frame.index <= noise_last)
        fillWithNoise(frame.image, static_cast<std::uint32_t>(frame.index));
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
  // The same 700 frames without noise: 0.0024 m (with noise: 0.0030, this machine). The issue's
  // bar is twice the clean run's.
  EXPECT_LT(r.ate.rmse, 2.0 * 0.0024);
  EXPECT_LT(after, 2.0 * 0.0024);
}

}  // namespace
}  // namespace ldsm
