// End-to-end: the odometry on rendered scenes with exact ground truth.
#include <gtest/gtest.h>
#include <spdlog/spdlog.h>

#include <cstdlib>

#include "ldsm/drivers/sim/sim_source.h"
#include "ldsm/eval/ate.h"
#include "ldsm/system.h"

namespace ldsm {
namespace {

struct RunResult {
  eval::AteResult ate;
  SystemStats stats;
  Trajectory trajectory;
  int lost_events = 0;
};

class CountingListener : public SystemListener {
 public:
  void onTrackingLost(const TrackingLostEvent&) override { ++lost; }
  int lost = 0;
};

RunResult runScene(const std::string& scene, std::int64_t frames, bool deterministic = true) {
  if (std::getenv("LDSM_DEBUG")) spdlog::set_level(spdlog::level::debug);
  drivers::sim::SimOptions opt;
  opt.frames = frames;
  drivers::sim::SimSource source(scene, opt);
  Config config;
  config.system.deterministic = deterministic;
  System system(config, source.geometricCalibration(), source.photometricCalibration());
  CountingListener listener;
  system.setListener(&listener);
  drivers::Frame frame;
  while (source.next(frame))
    system.submit({frame.image.view(), frame.timestamp, frame.exposure_ms});
  system.finish();
  RunResult r;
  r.trajectory = system.trajectory();
  r.stats = system.stats();
  r.lost_events = listener.lost;
  if (r.trajectory.size() >= 3) r.ate = eval::computeAte(source.groundTruth(), r.trajectory);
  std::printf("%s: %lld frames, %lld tracked, %lld keyframes, ATE %.5f m (%.3f %% of %.2f m)\n",
              scene.c_str(), static_cast<long long>(r.stats.frames),
              static_cast<long long>(r.stats.tracked_frames),
              static_cast<long long>(r.stats.keyframes), r.ate.rmse,
              100.0 * r.ate.rmse / std::max(r.ate.gt_path_length, 1e-9), r.ate.gt_path_length);
  return r;
}

// Measured: 0.01 % of the path (0.0005 m over 10 m).
TEST(SimOdometry, ForwardCorridorIsAccurate) {
  const RunResult r = runScene("forward", 300);
  EXPECT_EQ(r.stats.tracking_losses, 0);
  EXPECT_GE(r.stats.tracked_frames, 280);
  EXPECT_LT(r.ate.rmse, 0.002 * r.ate.gt_path_length);
}

// The first part of the corridor loop, through its first corner. Measured 0.019 % of the path
// (0.0017 m over 9.2 m). Until the initializer tried several motion hypotheses it was 1.8-4 %:
// starting at rest it settled on a translation 30 degrees off with a yaw of the wrong sign.
TEST(SimOdometry, LoopSceneFirstCornerTracks) {
  const RunResult r = runScene("loop", 300);
  EXPECT_EQ(r.stats.tracking_losses, 0);
  EXPECT_GE(r.stats.tracked_frames, 285);
  EXPECT_LT(r.ate.rmse, 0.002 * r.ate.gt_path_length);
}

TEST(SimOdometry, DeterministicModeIsBitIdentical) {
  const RunResult a = runScene("short", 0);
  const RunResult b = runScene("short", 0);
  ASSERT_EQ(a.trajectory.size(), b.trajectory.size());
  ASSERT_GT(a.trajectory.size(), 10u);
  for (size_t i = 0; i < a.trajectory.size(); ++i) {
    EXPECT_EQ(a.trajectory[i].timestamp, b.trajectory[i].timestamp);
    EXPECT_EQ(a.trajectory[i].pose.translation, b.trajectory[i].pose.translation) << i;
    EXPECT_EQ(a.trajectory[i].pose.rotation.coeffs(), b.trajectory[i].pose.rotation.coeffs()) << i;
  }
}

TEST(SimOdometry, ThreadedModeTracksLikeDeterministic) {
  const RunResult d = runScene("short", 0, true);
  const RunResult t = runScene("short", 0, false);
  EXPECT_EQ(t.stats.frames, d.stats.frames);
  EXPECT_EQ(t.stats.tracking_losses, 0);
  ASSERT_GT(t.trajectory.size(), 10u);
  EXPECT_LT(t.ate.rmse, 2.0 * d.ate.rmse + 1e-3);
}

}  // namespace
}  // namespace ldsm
