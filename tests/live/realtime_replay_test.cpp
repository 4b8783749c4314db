// Hardware-in-the-loop test of the live pipeline without a camera: a synthetic corridor
// (320x240, 150 frames at 30 fps, rendered once into memory) is replayed at its own timestamps
// through RealtimeReplaySource into a System in live mode (tracking and mapping threads, frames
// dropped when tracking falls behind). The engine keeps 600 points per keyframe instead of 2000
// (offline and replays alike): this corridor makes a keyframe every ~5 frames, and with the
// default density mapping cannot keep up with 4x on two loaded cores (70 % dropped, measured).
//
// Tolerance: at 1x and faster (4x where the machine sustains it) the trajectory's ATE must be
// within 2x the offline (deterministic) run's ATE + 1 cm, without tracking loss. At a speed the
// machine cannot sustain (frames 4x faster than the offline run's per-frame tracking cost, at least
// 20x), frames must be dropped and reported honestly: received + dropped == submitted, the received
// frames in order without duplicates, the newest frame never dropped.
#include <gtest/gtest.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <vector>

#include "ldsm/drivers/realtime_replay_source.h"
#include "ldsm/drivers/sim/sim_source.h"
#include "ldsm/eval/ate.h"
#include "ldsm/system.h"

namespace ldsm {
namespace {

constexpr int kFrames = 150;
constexpr double kFps = 30.0;

/// Replays frames held in memory (so that the replay measures the pipeline, not the renderer).
class MemorySource : public drivers::FrameSource {
 public:
  MemorySource(std::shared_ptr<const std::vector<drivers::Frame>> frames, drivers::SourceInfo info)
      : frames_(std::move(frames)), info_(std::move(info)) {}
  drivers::SourceInfo info() const override { return info_; }
  bool next(drivers::Frame& frame) override {
    if (next_ >= frames_->size()) return false;
    const drivers::Frame& f = (*frames_)[next_++];
    frame.index = f.index;
    frame.timestamp = f.timestamp;
    frame.exposure_ms = f.exposure_ms;
    frame.image.copyFrom(f.image.view());
    return true;
  }

 private:
  std::shared_ptr<const std::vector<drivers::Frame>> frames_;
  drivers::SourceInfo info_;
  std::size_t next_ = 0;
};

/// Timestamps of the frames the tracking received, in the order it received them.
class ReceivedListener : public SystemListener {
 public:
  void onFrame(const FrameEvent& e) override { received.push_back(e.timestamp); }
  void onTrackingLost(const TrackingLostEvent&) override { ++lost; }
  std::vector<double> received;
  int lost = 0;
};

struct RunResult {
  SystemStats stats;
  Trajectory trajectory;
  std::vector<double> received;
  std::int64_t submitted = 0;
  double ate = 0.0;
  double wall_s = 0.0;
  int lost = 0;
};

class RealtimeReplay : public ::testing::Test {
 protected:
  static Config engineConfig() {
    Config c;
    c.points.points_per_keyframe = 600;
    c.window.active_points = 600;
    return c;
  }

  static void SetUpTestSuite() {
    spdlog::set_level(spdlog::level::warn);
    drivers::sim::SimOptions o;
    o.width = 320;
    o.height = 240;
    o.fps = kFps;
    o.frames = kFrames;
    scene_ = std::make_unique<drivers::sim::SimSource>("forward", o);
    auto frames = std::make_shared<std::vector<drivers::Frame>>(kFrames);
    for (drivers::Frame& f : *frames) ASSERT_TRUE(scene_->next(f));
    frames_ = frames;
    Config deterministic = engineConfig();
    deterministic.system.deterministic = true;
    offline_ = run(deterministic, 0.0);
  }
  static void TearDownTestSuite() {
    scene_.reset();
    frames_.reset();
  }

  /// Runs the scene through a System; speed > 0 replays it in real time at that speed.
  static RunResult run(const Config& config, double speed) {
    System system(config, scene_->geometricCalibration(), scene_->photometricCalibration());
    ReceivedListener listener;
    system.setListener(&listener);
    std::unique_ptr<drivers::FrameSource> source =
        std::make_unique<MemorySource>(frames_, scene_->info());
    if (speed > 0.0)
      source = std::make_unique<drivers::RealtimeReplaySource>(std::move(source), speed);
    RunResult r;
    const auto start = std::chrono::steady_clock::now();
    drivers::Frame f;
    while (source->next(f)) {
      system.submit({f.image.view(), f.timestamp, f.exposure_ms});
      ++r.submitted;
    }
    system.finish();
    r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    r.stats = system.stats();
    r.trajectory = system.trajectory();
    r.received = listener.received;
    r.lost = listener.lost;
    if (r.trajectory.size() >= 3)
      r.ate = eval::computeAte(scene_->groundTruth(), r.trajectory).rmse;
    const StageTiming* latency = nullptr;
    for (const StageTiming& t : r.stats.latency)
      if (t.stage == "submit_to_tracked") latency = &t;
    std::printf(
        "speed %6.1fx: %3lld received, %3lld dropped, queue max %d, mapping backlog max %d, "
        "latency mean %.1f p99 %.1f ms, %zu poses, ATE %.4f m, %.2f s\n",
        speed, static_cast<long long>(r.stats.frames),
        static_cast<long long>(r.stats.dropped_frames), r.stats.max_queue_depth,
        r.stats.max_mapping_backlog, latency ? latency->mean_ms : 0.0,
        latency ? latency->p99_ms : 0.0, r.trajectory.size(), r.ate, r.wall_s);
    for (const StageTiming& t : r.stats.stages)  // where the time went
      if (t.count > 0)
        std::printf("  %s %lld x %.2f ms (p99 %.2f)", t.stage.c_str(),
                    static_cast<long long>(t.count), t.mean_ms, t.p99_ms);
    std::printf("\n");
    return r;
  }

  /// The replay speed the offline run suggests this machine sustains: the frame period over its
  /// mean cost of a frame (tracking and mapping on one thread; live, two threads share it).
  static double sustainedSpeed() {
    for (const StageTiming& t : offline_.stats.stages)
      if (t.stage == "total" && t.mean_ms > 0.0) return (1000.0 / kFps) / t.mean_ms;
    ADD_FAILURE() << "no stage \"total\" in the offline run's stats";
    return 1.0;
  }

  static RunResult replay(double speed) {
    Config live = engineConfig();
    live.system.live = true;
    return run(live, speed);
  }

  /// Every frame is accounted for: received by the tracking or dropped, in order, no duplicates.
  static void expectHonestAccounting(const RunResult& r) {
    EXPECT_EQ(r.submitted, kFrames);
    EXPECT_EQ(r.stats.submitted_frames, r.submitted);
    EXPECT_EQ(r.stats.frames + r.stats.dropped_frames, r.stats.submitted_frames);
    ASSERT_EQ(static_cast<std::int64_t>(r.received.size()), r.stats.frames);
    EXPECT_TRUE(std::is_sorted(r.received.begin(), r.received.end()));
    EXPECT_EQ(std::adjacent_find(r.received.begin(), r.received.end()), r.received.end());
    for (const double t : r.received) {
      const double i = t * kFps;
      EXPECT_NEAR(i, std::round(i), 1e-6) << t << " is not a frame of the sequence";
    }
    ASSERT_FALSE(r.received.empty());
    EXPECT_DOUBLE_EQ(r.received.back(), frames_->back().timestamp);  // newest never dropped
  }

  static void expectCloseToOffline(const RunResult& r, double speed) {
    expectHonestAccounting(r);
    // Replayed at the recorded rate (never faster).
    EXPECT_GE(r.wall_s, 0.95 * (kFrames - 1) / kFps / speed);
    EXPECT_EQ(r.lost, 0);
    EXPECT_EQ(r.stats.tracking_losses, 0);
    ASSERT_GE(r.trajectory.size(), 3u);
    // Frames before the map exists have no pose; all others must have one.
    EXPECT_GE(static_cast<double>(r.trajectory.size()),
              0.8 * static_cast<double>(r.stats.frames - 15));
    EXPECT_LE(r.ate, 2.0 * offline_.ate + 0.01)
        << "offline ATE " << offline_.ate << " m, replay at " << speed << "x";
  }

  static std::unique_ptr<drivers::sim::SimSource> scene_;
  static std::shared_ptr<const std::vector<drivers::Frame>> frames_;
  static RunResult offline_;
};

std::unique_ptr<drivers::sim::SimSource> RealtimeReplay::scene_;
std::shared_ptr<const std::vector<drivers::Frame>> RealtimeReplay::frames_;
RunResult RealtimeReplay::offline_;

TEST_F(RealtimeReplay, OfflineReferenceIsAccurate) {
  EXPECT_EQ(offline_.stats.frames, kFrames);
  EXPECT_EQ(offline_.stats.dropped_frames, 0);
  EXPECT_EQ(offline_.stats.tracking_losses, 0);
  EXPECT_LT(offline_.ate, 0.05);
}

TEST_F(RealtimeReplay, OneTimesRealTimeMatchesOffline) {
  expectCloseToOffline(replay(1.0), 1.0);
}

// Faster than real time: 4x where the machine sustains it (0.6 times the offline run's frame
// period over its mean cost of a frame: 4.2 ms measured on a 2-core EPYC, so 4x), slower on a
// slower machine, never below 1x. At a fixed 4x a machine five times slower (the test process on
// one core shared with four busy loops; offline 24 ms a frame) gave the initializer every ninth
// frame of the corridor, too far apart to initialise: no pose at all.
TEST_F(RealtimeReplay, FasterThanRealTimeMatchesOffline) {
  const double speed = std::clamp(0.6 * sustainedSpeed(), 1.0, 4.0);
  expectCloseToOffline(replay(speed), speed);
}

TEST_F(RealtimeReplay, UnsustainableSpeedReportsDrops) {
  // Frames 4x faster than the offline run's tracking cost per frame: no machine keeps up.
  double cost_ms = 0.0;
  for (const StageTiming& t : offline_.stats.stages)
    if (t.stage == "preprocess" || t.stage == "track") cost_ms += t.p50_ms;
  ASSERT_GT(cost_ms, 0.0);
  const double speed = std::clamp(4.0 * (1000.0 / kFps) / cost_ms, 20.0, 1000.0);
  const RunResult r = replay(speed);
  expectHonestAccounting(r);
  EXPECT_GT(r.stats.dropped_frames, 0) << "at " << speed << "x";
  EXPECT_EQ(r.stats.max_queue_depth, r.stats.queue_capacity);
}

}  // namespace
}  // namespace ldsm
