// Relocalisation when the map's answer is wrong. On vamr_desk_loop's checkerboard the map can
// place a frame a period off (PnP and the direct fit to one map keyframe both hold there), and a
// track started from such a pose fits almost as well as the right one. Near the window the
// tracking stage checks the map's pose against a second track from where the camera was last
// seen, and the one that fits the window better goes on (docs/map-reuse.md, "two starts"). These
// tests put the map's pose off on purpose, through the tracking stage's relocalisation filter, on
// the real sequence with frames left out (a gap in time, as black frames are refused by the
// System), and check that the run ends as if the map had been right.
#include <gtest/gtest.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>

#include "ldsm/eval/ate.h"
#include "pipeline/slam_pipeline.h"
#include "real_sequence.h"
#include "test_paths.h"

namespace ldsm {
namespace {

class LossListener : public SystemListener {
 public:
  void onTrackingLost(const TrackingLostEvent&) override { ++lost; }
  void onRelocalized(const RelocalizedEvent&) override { ++relocalized; }
  int lost = 0;
  int relocalized = 0;
};

struct WrongPoseRun {
  int answers_moved = 0;  ///< relocalisation answers the filter put off
  int lost = 0;
  SystemStats stats;
  eval::AteResult ate;
};

/// The first `frames` frames of vamr_desk_loop without frames [first, end), deterministic. Every
/// answer in which the map found the frame is moved by (dx, dy) median depths in the camera's x
/// and y before the tracking stage sees it. `adjust` may change the configuration.
WrongPoseRun runWithMapPoseOff(const std::string& folder, double dx, double dy, std::int64_t first,
                               std::int64_t end, std::int64_t frames,
                               const std::function<void(Config&)>& adjust = {}) {
  if (std::getenv("LDSM_DEBUG")) spdlog::set_level(spdlog::level::debug);
  const test::RealSequence seq = test::openRealSequence(folder);
  Config config;
  config.system.deterministic = true;
  if (adjust) adjust(config);
  SlamPipeline pipeline(config, seq.calibration.geometric, seq.calibration.photometric);
  LossListener listener;
  pipeline.setListener(&listener);
  WrongPoseRun r;
  pipeline.tracking().setRelocalizationFilter(
      [&](std::int64_t, double median_depth, RelocalizationResult& answer) {
        if (!answer.success) return;
        // The camera's centre moves by (dx, dy, 0) median depths in its own axes.
        const Eigen::Vector3d shift(dx * median_depth, dy * median_depth, 0.0);
        answer.T_c_w = SE3d(SO3d(), -shift) * answer.T_c_w;
        ++r.answers_moved;
      });
  drivers::Frame frame;
  while (seq.source->next(frame) && frame.index < frames) {
    if (frame.index >= first && frame.index < end) continue;  // the gap
    const bool exposure = std::isfinite(frame.exposure_ms) && config.photometric.use_exposure;
    pipeline.tracking().process(frame.image.view(), frame.index, frame.timestamp,
                                exposure ? frame.exposure_ms : 1.0);
  }
  pipeline.finish();
  pipeline.fillStats(r.stats);
  r.lost = listener.lost;
  r.ate = eval::computeAte(seq.ground_truth, pipeline.trajectory());
  std::printf(
      "vamr, frames %lld-%lld missing, map's pose off by (%.2f, %.2f) median depths: %d answers "
      "moved, %d lost, %lld relocalised, %lld new maps, %lld answers refused, ATE %.5f m over %zu "
      "poses\n",
      static_cast<long long>(first), static_cast<long long>(end - 1), dx, dy, r.answers_moved,
      r.lost, static_cast<long long>(r.stats.reuse.relocalizations),
      static_cast<long long>(r.stats.reuse.new_maps),
      static_cast<long long>(r.stats.reuse.relocalization_answers_refused), r.ate.rmse,
      r.ate.matched);
  return r;
}

// Frames 150-189 left out. The map finds the frames after the gap in keyframe 14 (and another
// candidate 0.25 median depths away), but the track from its pose fails and the wide search from
// the last pose fits at 70 % inliers: that one goes on, and the run ends as the clean one. With
// the map's answer moved 0.2 or 0.3 median depths (sideways, diagonally) the same must happen: a
// rule that resumed at the map's pose whenever the map confirms it would put the rest of the run
// off. The bar is twice DSO's figure for the sequence (0.0008-0.0009 m), as in the other gap
// tests (this run: 0.00104 m whatever the offset). About 4 s each.
void expectTheRunUnharmed(double dx, double dy) {
  const std::string folder = test::sharedData("vamr_desk_loop");
  if (folder.empty()) GTEST_SKIP() << "../shared/data/vamr_desk_loop is absent: real-data test";
  const WrongPoseRun r = runWithMapPoseOff(folder, dx, dy, 150, 190, 250);
  ASSERT_GE(r.answers_moved, 1) << "the map never found a frame after the gap: nothing was tested";
  EXPECT_EQ(r.lost, 1);
  EXPECT_EQ(r.stats.reuse.new_maps, 0);
  EXPECT_GT(r.ate.matched, 250u - 40u - 20u);
  EXPECT_LT(r.ate.rmse, 2.0 * 0.0009);
}

TEST(RelocalizationWrongPose, AMapPoseOffSidewaysLosesToTheTrackFromTheLastPose) {
  expectTheRunUnharmed(0.2, 0.0);
}

TEST(RelocalizationWrongPose, AMapPoseOffDiagonallyLosesToTheTrackFromTheLastPose) {
  expectTheRunUnharmed(0.15, -0.3);
}

// Frames 300-339 left out (the first 400 frames): the camera moved on during the gap, the window's
// track from the last pose does not fit (45-50 % inliers), and a frame the map found starts a new
// window at the map's pose, held there by the relocalisation anchor. With the answer moved 0.2
// median depths sideways the map keyframes around the moved pose align elsewhere, so the answer is
// refused until the window's own track holds again (18 refusals, within the first half of the 5 s
// relocalisation time), and the run ends as the clean one (0.00093 m). The control: with a
// relocalisation time of 2 s the check stops 1 s after the loss, before the gap (1.33 s) ends, so
// no answer is asked about and the moved one is taken (0.0237 m). About 8 s each.
TEST(RelocalizationWrongPose, AMapPoseTheNeighbouringKeyframesContradictIsRefused) {
  const std::string folder = test::sharedData("vamr_desk_loop");
  if (folder.empty()) GTEST_SKIP() << "../shared/data/vamr_desk_loop is absent: real-data test";
  const WrongPoseRun r = runWithMapPoseOff(folder, 0.2, 0.0, 300, 340, 400);
  ASSERT_GE(r.answers_moved, 1) << "the map never found a frame after the gap: nothing was tested";
  EXPECT_GE(r.stats.reuse.relocalization_answers_refused, 1);
  EXPECT_EQ(r.lost, 1);
  EXPECT_EQ(r.stats.reuse.new_maps, 0);
  EXPECT_GT(r.ate.matched, 300u);  // frames after the gap have poses
  EXPECT_LT(r.ate.rmse, 2.0 * 0.0009);

  const WrongPoseRun late = runWithMapPoseOff(
      folder, 0.2, 0.0, 300, 340, 400, [](Config& c) { c.reuse.relocalization_timeout_s = 2.0; });
  ASSERT_GE(late.answers_moved, 1);
  EXPECT_EQ(late.stats.reuse.relocalization_cross_checks, 0);
  EXPECT_EQ(late.stats.reuse.new_maps, 0);
  EXPECT_GT(late.ate.rmse, 5.0 * 2.0 * 0.0009) << "the moved answer no longer harms this run: the "
                                                  "test above no longer shows the check's effect";
}

}  // namespace
}  // namespace ldsm
