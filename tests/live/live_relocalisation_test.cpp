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
// holds either way (below). Measured on a 2-core AMD EPYC only: 0.00078-0.00112 m in 18 runs idle
// or with a busy loop on one core, each relocalised at frame 390; under two busy loops (about one
// core for the test's two threads) 8 of 9 runs relocalised at frame 390 (0.00086-0.00099 m) and
// one found no frame in the 2 s after the gap (51 frames dropped), which fails here. The ATE bar
// is twice DSO's figure for the sequence (0.0008-0.0009 m), as in the deterministic test. About
// 15 s (real time).
#include <gtest/gtest.h>
#include <spdlog/sinks/ringbuffer_sink.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <algorithm>
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

/// While alive, the debug log goes to a ring of the last `lines` messages and warnings and errors
/// to stdout as with spdlog's default logger; the previous default logger comes back afterwards.
/// When the test has failed by then (an ASSERT included), the kept messages from the first that
/// contains `from` on are printed: a failure under CI's load then shows what tracking and the
/// relocaliser decided (2026-12-07's failure said only how many poses there were). From the loss
/// to the end of a run that relocalises at once, about 60 messages are logged: 600 also keep a
/// search that takes every frame after the gap.
class FailureDebugLog {
 public:
  FailureDebugLog(std::size_t lines, std::string from)
      : from_(std::move(from)),
        previous_(spdlog::default_logger()),
        ring_(std::make_shared<spdlog::sinks::ringbuffer_sink_mt>(lines)) {
    auto console = std::make_shared<spdlog::sinks::stdout_color_sink_mt>();
    console->set_level(std::getenv("LDSM_DEBUG") ? spdlog::level::debug : spdlog::level::warn);
    ring_->set_level(spdlog::level::debug);
    auto logger = std::make_shared<spdlog::logger>("live_relocalisation_test",
                                                   spdlog::sinks_init_list{console, ring_});
    logger->set_level(spdlog::level::debug);
    spdlog::set_default_logger(logger);
  }
  ~FailureDebugLog() {
    if (::testing::Test::HasFailure()) dump();
    spdlog::set_default_logger(previous_);
  }
  FailureDebugLog(const FailureDebugLog&) = delete;
  FailureDebugLog& operator=(const FailureDebugLog&) = delete;

 private:
  void dump() const {
    const std::vector<std::string> lines = ring_->last_formatted();
    const auto first = std::find_if(lines.begin(), lines.end(), [&](const std::string& line) {
      return line.find(from_) != std::string::npos;
    });
    if (first == lines.end()) {
      std::printf("  the debug log (\"%s\" not among the %zu kept lines):\n", from_.c_str(),
                  lines.size());
    } else {
      std::printf("  the debug log from \"%s\" on:\n", from_.c_str());
    }
    for (auto it = first == lines.end() ? lines.begin() : first; it != lines.end(); ++it) {
      std::printf("    %s", it->c_str());
    }
  }

  std::string from_;
  std::shared_ptr<spdlog::logger> previous_;
  std::shared_ptr<spdlog::sinks::ringbuffer_sink_mt> ring_;
};

/// What the run's events say: every frame tracking received (dropped and black frames never reach
/// it: no event), the losses and the relocalisations.
class RunListener : public SystemListener {
 public:
  struct ReceivedFrame {
    double timestamp = 0.0;
    bool has_pose = false;
    TrackingStatus status = TrackingStatus::Initializing;
  };
  void onFrame(const FrameEvent& e) override {
    frames.push_back({e.timestamp, e.has_pose, e.status});
  }
  void onTrackingLost(const TrackingLostEvent&) override { ++lost; }
  void onRelocalized(const RelocalizedEvent& e) override { found.push_back(e); }
  std::vector<ReceivedFrame> frames;  ///< in the order tracking received them
  int lost = 0;
  std::vector<RelocalizedEvent> found;
};

TEST(LiveRelocalisation, VamrDeskLoopResumesInItsMapAfterFortyBlackFramesInRealTime) {
  const std::string folder = test::sharedData("vamr_desk_loop");
  if (folder.empty())
    GTEST_SKIP() << "../shared/data/vamr_desk_loop is absent: real-data test skipped";
  const FailureDebugLog failure_debug_log(600, "tracking lost");
  const auto desc = drivers::describeDataset(folder);
  const auto calib = drivers::loadDatasetCalibration(desc);
  const Trajectory gt =
      drivers::readTrajectory(desc.groundtruth_file, desc.groundtruth_format, &desc.timestamps);
  Config config;  // the defaults, as `ldsm run --realtime` (map reuse and loop closure on)
  config.system.live = true;
  RunListener listener;  // outlives the system's threads
  System system(config, calib.geometric, calib.photometric);
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
  // Which of the frames tracking received have a pose: every one from the map's start to the gap,
  // and every one from the relocalised frame to the end, but for frames that live tracking leaves
  // without a pose while still tracking (one that fails while a keyframe is being mapped: the next
  // frame has the new reference; TrackingStage::trackStep). The old count allowed 20 frames
  // without a pose, the initialisation's 12 or so among them; those left while tracking may be up
  // to 10. The map starts within 1.5 s: 0.4-0.57 s on an idle machine, 0.67-0.87 s under two busy
  // loops (the initialiser's thread falls behind and frames go by while it works). Relocalising
  // may take several attempts, each dropping frames while it runs: on CI (2026-12-07, the test
  // alone, 29 frames dropped) frame 390 did not resume in the window and the map found the seventh
  // frame tracking received after the gap, 1.17 s after the first clean one (25 poses after it).
  // It must come within 1.5 s, and at least 15 poses (half a second) must follow.
  ASSERT_EQ(listener.found.size(), 1u);
  const double resumed_at = listener.found.front().timestamp;
  const double first_clean = desc.timestamps[static_cast<std::size_t>(kBlackEnd)];
  double map_start = -1.0;
  std::size_t posed = 0, posed_after_resume = 0, left_while_tracking = 0;
  std::size_t unposed_before_gap = 0, unposed_after_resume = 0;
  for (const RunListener::ReceivedFrame& f : listener.frames) {
    if (f.has_pose) {
      ++posed;
      if (map_start < 0.0) map_start = f.timestamp;
      if (f.timestamp >= resumed_at) ++posed_after_resume;
      continue;
    }
    if (map_start < 0.0) continue;  // initialising
    if (f.status == TrackingStatus::Tracking) {
      ++left_while_tracking;
      continue;
    }
    if (f.timestamp < gap_start) ++unposed_before_gap;
    if (f.timestamp >= resumed_at) ++unposed_after_resume;
  }
  std::printf(
      "  %zu frames received, %zu with a pose (%zu after the relocalisation), %zu left without "
      "one while tracking; the map from %.2f s, resumed %.2f s after the first clean frame\n",
      listener.frames.size(), posed, posed_after_resume, left_while_tracking,
      map_start - desc.timestamps.front(), resumed_at - first_clean);
  // Black frames are rejected before tracking: no frame event.
  EXPECT_EQ(static_cast<std::int64_t>(listener.frames.size()), s.frames - s.rejected_frames);
  EXPECT_LE(s.rejected_frames, kBlackEnd - kBlackFirst);
  EXPECT_GE(map_start, 0.0);
  EXPECT_LE(map_start - desc.timestamps.front(), 1.5);
  EXPECT_EQ(unposed_before_gap, 0u) << "lost between the map's start and the gap";
  EXPECT_EQ(unposed_after_resume, 0u) << "lost after the relocalisation";
  EXPECT_LE(left_while_tracking, 10u);
  EXPECT_LE(resumed_at - first_clean, 1.5);
  EXPECT_GE(posed_after_resume, 15u);
  EXPECT_EQ(ate.matched, trajectory.size());
  EXPECT_LT(ate.rmse, 2.0 * 0.0009);
}

}  // namespace
}  // namespace ldsm
