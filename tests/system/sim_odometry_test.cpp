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
};

RunResult runScene(const std::string& scene, std::int64_t frames, bool calibrated = true) {
  if (std::getenv("LDSM_DEBUG")) spdlog::set_level(spdlog::level::debug);
  drivers::sim::SimOptions opt;
  opt.frames = frames;
  drivers::sim::SimSource source(scene, opt);
  Config config;
  config.system.deterministic = true;
  System system(config, source.geometricCalibration(),
                calibrated ? source.photometricCalibration() : PhotometricCalibration{});
  drivers::Frame frame;
  while (source.next(frame))
    system.submit({frame.image.view(), frame.timestamp, frame.exposure_ms});
  system.finish();
  RunResult r;
  r.trajectory = system.trajectory();
  r.stats = system.stats();
  if (r.trajectory.size() >= 3) r.ate = eval::computeAte(source.groundTruth(), r.trajectory);
  return r;
}

TEST(SimOdometry, ForwardScene) {
  const RunResult r = runScene("forward", std::getenv("LDSM_FRAMES") ? std::atoi(std::getenv("LDSM_FRAMES")) : 300);
  std::printf("frames %lld tracked %lld keyframes %lld inits %lld lost %lld\n",
              static_cast<long long>(r.stats.frames), static_cast<long long>(r.stats.tracked_frames),
              static_cast<long long>(r.stats.keyframes),
              static_cast<long long>(r.stats.initializations),
              static_cast<long long>(r.stats.tracking_losses));
  for (const auto& s : r.stats.stages)
    std::printf("  %-10s n=%lld mean %.2f ms p99 %.2f ms\n", s.stage.c_str(),
                static_cast<long long>(s.count), s.mean_ms, s.p99_ms);
  std::printf("ATE rmse %.4f m over %d poses, path %.2f m\n", r.ate.rmse, static_cast<int>(r.ate.matched),
              r.ate.gt_path_length);
  EXPECT_EQ(r.stats.tracking_losses, 0);
  EXPECT_LT(r.ate.rmse, 0.01 * r.ate.gt_path_length);
}

}  // namespace
}  // namespace ldsm
