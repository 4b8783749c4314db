// Relocalisation in the live pipeline (tracking and mapping on their own threads, frames paced at
// the recorded rate and dropped when tracking falls behind), on real images: vamr_desk_loop's
// first 450 frames with frames 350-389 (1.3 s) black, as `ldsm run --dataset DIR --realtime` runs
// it. The deterministic run of the same frames is
// MapReuse.VamrDeskLoopResumesInItsMapAfterFortyBlackFrames (tests/system); this one covers what
// only the threads show: the mapping thread still integrating the keyframe before the loss while
// tracking looks for the frame, the map's keyframes changing under the relocaliser, frames
// dropped when a relocalisation attempt takes long. In the runs measured frame 390 resumed in the
// window by the plain rule (1.7-1.8 times the residual before the loss, 69-80 % inliers), not by
// the map's confirmation, and no frame was dropped (docs/map-reuse.md, "The map confirms the
// window's track"). On CI (2026-12-07) it did not: the map relocaliser found the seventh frame
// tracking received after the gap, 29 frames dropped while its attempts ran, so the test asks what
// holds either way (below). Measured on a 2-core AMD EPYC only: 0.00078-0.00102 m in 7 runs (2 of
// them with a busy loop on one core), 0.00086-0.00092 m in 6 under two busy loops; the bar is twice
// DSO's figure for the sequence (0.0008-0.0009 m), as in the deterministic test. About 15 s (real
// time).
#include <gtest/gtest.h>
#include <spdlog/sinks/ringbuffer_sink.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "ldsm/drivers/dataset_calibration.h"
#include "ldsm/drivers/dataset_description.h"
#include "ldsm/drivers/dataset_source.h"
#include "ldsm/drivers/realtime_replay_source.h"
#include "ldsm/drivers/trajectory_io.h"
#include "ldsm/error.h"
#include "ldsm/eval/ate.h"
#include "ldsm/system.h"
#include "test_paths.h"

namespace ldsm {
namespace {

constexpr std::int64_t kFrames = 450;
constexpr std::int64_t kBlackFirst = 350, kBlackEnd = 390;

/// The dataset's first kFrames frames, those in [kBlackFirst, kBlackEnd) black (a covered lens).
class BlackedOutSource : public drivers::FrameSource {
 public:
  explicit BlackedOutSource(std::unique_ptr<drivers::FrameSource> source)
      : source_(std::move(source)) {}
  drivers::SourceInfo info() const override { return source_->info(); }
  bool next(drivers::Frame& frame) override {
    if (!source_->next(frame) || frame.index >= kFrames) return false;
    if (frame.index >= kBlackFirst && frame.index < kBlackEnd) frame.image.fill(0);
    return true;
  }

 private:
  std::unique_ptr<drivers::FrameSource> source_;
};

/// While alive, the debug log goes to a ring of the last `lines` messages (printed by dump()) and
/// warnings and errors to stderr as usual; the previous default logger comes back afterwards. A
/// failure under CI's load then shows what tracking and the relocaliser decided (2026-12-07's
/// failure said only how many poses there were).
class RecentDebugLog {
 public:
  explicit RecentDebugLog(std::size_t lines)
      : previous_(spdlog::default_logger()),
        ring_(std::make_shared<spdlog::sinks::ringbuffer_sink_mt>(lines)) {
    auto console = std::make_shared<spdlog::sinks::stderr_color_sink_mt>();
    console->set_level(std::getenv("LDSM_DEBUG") ? spdlog::level::debug : spdlog::level::warn);
    ring_->set_level(spdlog::level::debug);
    auto logger = std::make_shared<spdlog::logger>("live_relocalisation_test",
                                                   spdlog::sinks_init_list{console, ring_});
    logger->set_level(spdlog::level::debug);
    spdlog::set_default_logger(logger);
  }
  ~RecentDebugLog() { spdlog::set_default_logger(previous_); }
  RecentDebugLog(const RecentDebugLog&) = delete;
  RecentDebugLog& operator=(const RecentDebugLog&) = delete;
  /// The kept messages from the first that contains `from` on (all when none does).
  void dump(const std::string& from) const {
    const std::vector<std::string> lines = ring_->last_formatted();
    std::size_t first = 0;
    for (std::size_t i = 0; i < lines.size(); ++i)
      if (lines[i].find(from) != std::string::npos) {
        first = i;
        break;
      }
    std::printf("  the debug log from \"%s\" on (%zu of %zu kept lines):\n", from.c_str(),
                lines.size() - first, lines.size());
    for (std::size_t i = first; i < lines.size(); ++i) std::printf("    %s", lines[i].c_str());
  }

 private:
  std::shared_ptr<spdlog::logger> previous_;
  std::shared_ptr<spdlog::sinks::ringbuffer_sink_mt> ring_;
};

class LossListener : public SystemListener {
 public:
  void onFrame(const FrameEvent& e) override { frames.push_back({e.timestamp, e.has_pose}); }
  void onTrackingLost(const TrackingLostEvent&) override { ++lost; }
  void onRelocalized(const RelocalizedEvent& e) override { found.push_back(e); }
  struct Processed {
    double timestamp = 0.0;
    bool has_pose = false;
  };
  std::vector<Processed> frames;  ///< every frame tracking received, in order (none dropped)
  int lost = 0;
  std::vector<RelocalizedEvent> found;
};

TEST(LiveRelocalisation, VamrDeskLoopResumesInItsMapAfterFortyBlackFramesInRealTime) {
  const std::string folder = test::sharedData("vamr_desk_loop");
  if (folder.empty())
    GTEST_SKIP() << "../shared/data/vamr_desk_loop is absent: real-data test skipped";
  const RecentDebugLog log(600);
  const auto desc = drivers::describeDataset(folder);
  const auto calib = drivers::loadDatasetCalibration(desc);
  const Trajectory gt =
      drivers::readTrajectory(desc.groundtruth_file, desc.groundtruth_format, &desc.timestamps);
  Config config;  // the defaults, as `ldsm run --realtime` (map reuse and loop closure on)
  config.system.live = true;
  System system(config, calib.geometric, calib.photometric);
  LossListener listener;
  system.setListener(&listener);
  drivers::RealtimeReplaySource source(
      std::make_unique<BlackedOutSource>(drivers::openDataset(desc)), 1.0);
  drivers::Frame frame;
  std::int64_t submitted = 0;
  while (source.next(frame)) {
    system.submit({frame.image.view(), frame.timestamp, frame.exposure_ms});
    ++submitted;
  }
  system.finish();
  const SystemStats s = system.stats();
  const Trajectory trajectory = system.trajectory();
  const eval::AteResult ate = eval::computeAte(gt, trajectory);
  int other_map = 0;
  for (const StampedPose& p : trajectory) other_map += p.map != 0 ? 1 : 0;
  std::printf(
      "live vamr, 40 black frames: %lld submitted, %lld dropped, %lld lost, %lld relocalised, "
      "%lld new maps, ATE %.5f m over %zu poses, replay %.1f ms late at most\n",
      static_cast<long long>(submitted), static_cast<long long>(s.dropped_frames),
      static_cast<long long>(s.tracking_losses), static_cast<long long>(s.reuse.relocalizations),
      static_cast<long long>(s.reuse.new_maps), ate.rmse, ate.matched, source.maxLatenessMs());
  for (const RelocalizedEvent& e : listener.found)
    std::printf(
        "  relocalised at frame %lld after %.2f s (tracking reference keyframe %d, map "
        "keyframe %d)\n",
        static_cast<long long>(e.frame_index), e.lost_seconds, e.keyframe_id, e.map_keyframe_id);
  // Where an error comes from (a failure under ctest's load, 2026-12-06, said only ATE 0.0117 m):
  // the poses before the gap and those after it, each aligned on its own (a relocalisation a
  // checkerboard period off leaves both small and the whole large), and the loop corrections
  // that moved keyframes.
  const double gap_start = desc.timestamps[static_cast<std::size_t>(kBlackFirst)];
  Trajectory before, after;
  for (const StampedPose& p : trajectory) (p.timestamp < gap_start ? before : after).push_back(p);
  const auto segmentAte = [&](const Trajectory& t) {
    try {
      return eval::computeAte(gt, t).rmse;
    } catch (const InputError&) {
      return -1.0;  // too few poses matched to the ground truth: printed as -1
    }
  };
  std::printf("  ATE before the gap %.5f m (%zu poses), after it %.5f m (%zu poses)\n",
              segmentAte(before), before.size(), segmentAte(after), after.size());
  for (const LoopClosureEvent& l : s.loops)
    if (l.corrected_keyframes > 0)
      std::printf("  loop %d -> %d corrected %d keyframes (chi2 %.1f, scale %.4f)\n",
                  l.current_keyframe_id, l.matched_keyframe_id, l.corrected_keyframes, l.drift_chi2,
                  l.scale);
  EXPECT_EQ(submitted, kFrames);
  EXPECT_EQ(listener.lost, 1);
  EXPECT_EQ(s.reuse.relocalizations, 1);
  EXPECT_EQ(s.reuse.new_maps, 0);
  EXPECT_EQ(other_map, 0) << "poses reported in a second map's frame";
  // Which of the frames tracking received (dropped ones never reach it) have a pose: every one
  // from the map's start to the gap, and every one from the relocalised frame to the end. The map
  // starts within 1.5 s: 0.4 s (12 frames) on an idle machine, 0.67-0.87 s under two busy loops
  // (the initialiser's thread falls behind and frames go by while it works). Relocalising may take
  // several attempts, each dropping frames while it runs: on CI (2026-12-07, the test alone, 29
  // frames dropped) frame 390 did not resume in the window and the map found the seventh frame
  // tracking received after the gap, 1.17 s after the first clean one. It must come within 1.5 s,
  // so that at least 15 poses after it (half a second) are measured.
  ASSERT_EQ(listener.found.size(), 1u);
  const double resumed_at = listener.found.front().timestamp;
  const double first_clean = desc.timestamps[static_cast<std::size_t>(kBlackEnd)];
  double map_start = -1.0;
  std::size_t posed = 0, unposed_before_gap = 0, unposed_after_resume = 0;
  for (const LossListener::Processed& f : listener.frames) {
    posed += f.has_pose ? 1 : 0;
    if (f.has_pose && map_start < 0.0) map_start = f.timestamp;
    if (f.has_pose) continue;
    if (map_start >= 0.0 && f.timestamp < gap_start) ++unposed_before_gap;
    if (f.timestamp >= resumed_at) ++unposed_after_resume;
  }
  std::printf(
      "  %zu frames received, %zu with a pose; the map from %.2f s, resumed %.2f s after the "
      "first clean frame\n",
      listener.frames.size(), posed, map_start - desc.timestamps.front(), resumed_at - first_clean);
  EXPECT_GE(map_start, 0.0);
  EXPECT_LE(map_start - desc.timestamps.front(), 1.5);
  // Black frames are rejected before tracking (no frame event).
  EXPECT_GE(listener.frames.size() + (kBlackEnd - kBlackFirst) + s.dropped_frames, kFrames);
  EXPECT_EQ(unposed_before_gap, 0u) << "frames between the map's start and the gap without a pose";
  EXPECT_EQ(unposed_after_resume, 0u) << "frames after the relocalisation without a pose";
  EXPECT_LE(resumed_at - first_clean, 1.5);
  // The trajectory also holds the initialiser's first frames, posed once the map starts.
  EXPECT_GE(trajectory.size(), posed);
  EXPECT_EQ(ate.matched, trajectory.size());
  EXPECT_LT(ate.rmse, 2.0 * 0.0009);
  if (::testing::Test::HasFailure()) log.dump("tracking lost");
}

}  // namespace
}  // namespace ldsm
