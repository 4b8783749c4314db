// End-to-end: the odometry on rendered scenes with exact ground truth.
#include <gtest/gtest.h>
#include <spdlog/spdlog.h>

#include <cmath>
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

/// The scene's exact calibration, or one that claims a radial distortion k1 the images do not
/// have (rectification then leaves a residual distortion of about -k1 in them).
GeometricCalibration toldCalibration(const drivers::sim::SimSource& source, double told_k1,
                                     double told_focal_scale = 1.0) {
  GeometricCalibration told = source.geometricCalibration();
  if (told_focal_scale != 1.0) {
    told.input.fx *= told_focal_scale;
    told.input.fy *= told_focal_scale;
    if (told.output.mode == OutputMode::Explicit && !told.output.relative) {
      told.output.fx *= told_focal_scale;
      told.output.fy *= told_focal_scale;
    }
  }
  if (told_k1 == 0.0) return told;
  told.input.model = CameraModelType::RadTan;
  told.input.distortion = {told_k1, 0.0, 0.0, 0.0};
  told.output.mode = OutputMode::Explicit;
  told.output.relative = false;
  told.output.fx = told.input.fx;
  told.output.fy = told.input.fy;
  told.output.cx = told.input.cx;
  told.output.cy = told.input.cy;
  told.output.width = told.input.width;
  told.output.height = told.input.height;
  return told;
}

RunResult runScene(const std::string& scene, std::int64_t frames, bool deterministic = true,
                   double told_k1 = 0.0, bool refine_radial = true, double told_focal_scale = 1.0,
                   bool refine_focal = false) {
  if (std::getenv("LDSM_DEBUG")) spdlog::set_level(spdlog::level::debug);
  drivers::sim::SimOptions opt;
  opt.frames = frames;
  drivers::sim::SimSource source(scene, opt);
  Config config;
  config.system.deterministic = deterministic;
  config.calibration.refine_radial = refine_radial;
  config.calibration.refine_focal = refine_focal;
  System system(config, toldCalibration(source, told_k1, told_focal_scale),
                source.photometricCalibration());
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
  // Exact calibration: the radial correction stays off (pure forward motion says little about it).
  EXPECT_LT(std::abs(r.stats.radial_estimate), 0.003);
  EXPECT_EQ(r.stats.radial_applied, 0.0);
}

// The first part of the corridor loop, through its first corner. Measured 0.019 % of the path
// (0.0017 m over 9.2 m). Until the initializer tried several motion hypotheses it was 1.8-4 %:
// starting at rest it settled on a translation 30 degrees off with a yaw of the wrong sign.
TEST(SimOdometry, LoopSceneFirstCornerTracks) {
  const RunResult r = runScene("loop", 300);
  EXPECT_EQ(r.stats.tracking_losses, 0);
  EXPECT_GE(r.stats.tracked_frames, 285);
  EXPECT_LT(r.ate.rmse, 0.002 * r.ate.gt_path_length);
  EXPECT_LT(std::abs(r.stats.radial_estimate), 0.003);
  EXPECT_EQ(r.stats.radial_applied, 0.0);
}

// The corridor loop started 30 and 35 frames in (the camera driving straight down the corridor).
// The initializer's motion hypotheses then had a wrong one (translation 24 degrees off with 1.6
// degrees of yaw) at 6 % less capped energy than the true motion, with 1.3-1.6 times its inlier
// RMS; it won, and the map collapsed in scale by the first corner (ATE 0.92 and 0.84 m). Now a
// hypothesis with clearly lower inlier RMS leads: measured 0.0015 and 0.0020 m (starts 0-60 in
// steps of 5-10: 0.0008-0.0020 m).
TEST(SimOdometry, LoopSceneTracksFromAnyStart) {
  for (const std::int64_t start : {30, 35}) {
    drivers::sim::SimOptions opt;
    opt.frames = start + 280;
    drivers::sim::SimSource source("loop", opt);
    source.seek(start);
    Config config;
    config.system.deterministic = true;
    System system(config, source.geometricCalibration(), source.photometricCalibration());
    drivers::Frame frame;
    while (source.next(frame))
      system.submit({frame.image.view(), frame.timestamp, frame.exposure_ms});
    system.finish();
    const SystemStats stats = system.stats();
    const eval::AteResult ate = eval::computeAte(source.groundTruth(), system.trajectory());
    std::printf("loop from frame %lld: %lld tracked, ATE %.5f m over %.2f m\n",
                static_cast<long long>(start), static_cast<long long>(stats.tracked_frames),
                ate.rmse, ate.gt_path_length);
    EXPECT_EQ(stats.tracking_losses, 0) << "start " << start;
    EXPECT_GE(stats.tracked_frames, 265) << "start " << start;
    EXPECT_LT(ate.rmse, 0.002 * ate.gt_path_length) << "start " << start;
  }
}

// The calibration claims a radial distortion k1 = -0.01 the rendered images do not have (4 pixels
// at the image corners after rectification). The online refinement finds the residual
// distortion (+0.01). Measured: ATE 0.0023 m with it, 0.0250 m without.
TEST(SimOdometry, RadialRefinementRepairsAWrongDistortion) {
  const RunResult on = runScene("loop", 300, true, -0.01, true);
  const RunResult off = runScene("loop", 300, true, -0.01, false);
  EXPECT_EQ(on.stats.tracking_losses, 0);
  EXPECT_NEAR(on.stats.radial_applied, 0.01, 0.002);
  EXPECT_EQ(off.stats.radial_applied, 0.0);
  EXPECT_LT(on.ate.rmse, 0.3 * off.ate.rmse);
  EXPECT_LT(on.ate.rmse, 0.001 * on.ate.gt_path_length);
}

// The calibration claims focal lengths 5 % short. With the focal refinement on, the window's
// envelope steps see it in the loop scene's corner (a rotation moves border pixels by
// f (1 + x^2) theta, which a rotation alone cannot match with a wrong f). Measured: applied fx
// 381.5 for a truth of 381.4 (told 362.3), ATE 0.0022 m against 0.044 m without the refinement
// and 0.0014 m with the exact calibration. (Until the envelope left the marginalisation prior
// out, a quarter of the error was found: fx 367.2, ATE 0.037 m; docs/engine.md.)
TEST(SimOdometry, FocalRefinementMovesAWrongFocalLengthTowardsTheTruth) {
  const RunResult on = runScene("loop", 300, true, 0.0, true, 0.95, true);
  const RunResult off = runScene("loop", 300, true, 0.0, true, 0.95, false);
  const CalibrationStats& c = on.stats.calibration;
  std::printf(
      "focal refinement: fx told %.2f, applied %.2f, estimate scale %.4f, ATE on %.5f, "
      "off %.5f m\n",
      c.configured.fx, c.applied.fx, c.focal_scale_estimate, on.ate.rmse, off.ate.rmse);
  const double true_fx = c.configured.fx / 0.95;
  EXPECT_NEAR(c.applied.fx / true_fx, 1.0, 0.005);
  EXPECT_EQ(off.stats.calibration.applied.fx, off.stats.calibration.configured.fx);
  EXPECT_LT(on.ate.rmse, 0.2 * off.ate.rmse);
}

// Threaded, not live (`ldsm run --dataset` without --deterministic): a frame waits for the
// keyframe being mapped, so the odometry makes the keyframes deterministic mode makes (within
// what the threads' timing changes; 7/8 of them). Measured at the default keyframe rate of
// 2026-11: 63 keyframes, ATE 0.0011-0.0013 m (deterministic: 63, 0.0014 m). Before, tracking
// never waited: 23-31 keyframes (about half) and 0.75-2.2 m on this fast corridor.
TEST(SimOdometry, OfflineThreadedModeMakesEveryKeyframe) {
  const RunResult d = runScene("loop", 300, true);
  const RunResult r = runScene("loop", 300, false);
  EXPECT_EQ(r.stats.tracking_losses, 0);
  EXPECT_GE(r.stats.keyframes * 8, d.stats.keyframes * 7);
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
