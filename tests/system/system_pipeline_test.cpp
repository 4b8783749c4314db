// The threaded System's frame pipeline: pool + lock-free queue between submit() and the tracking
// thread. Live mode drops the oldest queued frames while tracking is behind (and never makes
// submit() wait); offline mode makes submit() wait and loses nothing. Also the latest pose, the
// pipeline statistics, the new system.* settings and CPU affinity.
#include <gtest/gtest.h>

#if defined(__linux__)
#include <pthread.h>
#include <sched.h>
#endif

#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <thread>
#include <vector>

#include "ldsm/drivers/config_yaml.h"
#include "ldsm/drivers/sim/sim_source.h"
#include "ldsm/error.h"
#include "ldsm/system.h"

namespace ldsm {
namespace {

using namespace std::chrono_literals;

GeometricCalibration smallCamera(int w = 160, int h = 120) {
  GeometricCalibration g;
  g.input = {CameraModelType::Pinhole, 120.0, 120.0, (w - 1) / 2.0, (h - 1) / 2.0, {}, w, h};
  g.output.mode = OutputMode::None;
  g.output.width = w;
  g.output.height = h;
  return g;
}

ImageU8 texturedImage(int w, int h) {
  ImageU8 img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      img(x, y) = static_cast<std::uint8_t>(128 + 60 * std::sin(0.21 * x) * std::cos(0.17 * y));
  return img;
}

/// Records the timestamp of every processed frame; blocks the tracking thread inside the first
/// onFrame() until released.
class BlockingListener : public SystemListener {
 public:
  void onFrame(const FrameEvent& e) override {
    {
      std::lock_guard<std::mutex> lock(mutex);
      timestamps.push_back(e.timestamp);
    }
    if (!entered.exchange(true))
      while (!released.load()) std::this_thread::sleep_for(1ms);
  }
  void waitUntilBlocked() const {
    while (!entered.load()) std::this_thread::sleep_for(1ms);
  }
  std::mutex mutex;
  std::vector<double> timestamps;
  std::atomic<bool> entered{false};
  std::atomic<bool> released{false};
};

Config threaded(bool live, int pool = 6) {
  Config c;
  c.system.live = live;
  c.system.frame_pool_size = pool;
  return c;
}

TEST(SystemPipeline, LiveModeDropsTheOldestQueuedFramesAndNeverWaits) {
  System system(threaded(true), smallCamera());
  BlockingListener listener;
  system.setListener(&listener);
  const ImageU8 img = texturedImage(160, 120);
  system.submit({img.view(), 0.0});
  listener.waitUntilBlocked();  // frame 0 is being tracked, holding its buffer
  // Tracking is stuck: the queue (4 frames for a pool of 6) fills, then every submit drops the
  // oldest queued frame. None of these may wait.
  const auto start = std::chrono::steady_clock::now();
  for (int i = 1; i <= 10; ++i) system.submit({img.view(), 0.1 * i});
  EXPECT_LT(std::chrono::steady_clock::now() - start, 2s);
  listener.released = true;
  system.finish();
  const SystemStats s = system.stats();
  EXPECT_EQ(s.submitted_frames, 11);
  EXPECT_EQ(s.dropped_frames, 6);
  EXPECT_EQ(s.frames, 5);
  EXPECT_EQ(s.frames + s.dropped_frames, s.submitted_frames);
  EXPECT_EQ(s.queue_capacity, 4);
  EXPECT_EQ(s.max_queue_depth, 4);
  // Frame 0, then the four newest: 7..10.
  ASSERT_EQ(listener.timestamps.size(), 5u);
  const double expected[] = {0.0, 0.7, 0.8, 0.9, 1.0};
  for (int i = 0; i < 5; ++i) EXPECT_NEAR(listener.timestamps[i], expected[i], 1e-12) << i;
}

TEST(SystemPipeline, OfflineModeMakesSubmitWaitAndLosesNothing) {
  System system(threaded(false), smallCamera());
  BlockingListener listener;
  system.setListener(&listener);
  const ImageU8 img = texturedImage(160, 120);
  std::atomic<int> returned{0};
  constexpr int kFrames = 20;
  std::thread producer([&] {
    for (int i = 0; i < kFrames; ++i) {
      system.submit({img.view(), 0.1 * i});
      ++returned;
    }
  });
  listener.waitUntilBlocked();
  std::this_thread::sleep_for(300ms);
  // Frame 0 is being tracked, frames 1..4 fill the queue; the submit of frame 5 waits.
  EXPECT_EQ(returned.load(), 5);
  listener.released = true;
  producer.join();
  system.finish();
  const SystemStats s = system.stats();
  EXPECT_EQ(s.submitted_frames, kFrames);
  EXPECT_EQ(s.dropped_frames, 0);
  EXPECT_EQ(s.frames, kFrames);
  ASSERT_EQ(listener.timestamps.size(), static_cast<std::size_t>(kFrames));
  for (int i = 0; i < kFrames; ++i) EXPECT_NEAR(listener.timestamps[i], 0.1 * i, 1e-12) << i;
}

TEST(SystemPipeline, QueueCapacityFollowsThePoolSize) {
  for (const auto& [pool, capacity] : {std::pair{4, 2}, {5, 2}, {6, 4}, {9, 4}, {10, 8}}) {
    System system(threaded(true, pool), smallCamera());
    EXPECT_EQ(system.stats().queue_capacity, capacity) << "pool " << pool;
  }
}

/// Keeps the pose of the last frame that had one, as the listener saw it.
class LastPoseListener : public SystemListener {
 public:
  void onFrame(const FrameEvent& e) override {
    if (!e.has_pose) return;
    last = StampedPose{e.timestamp, e.pose};
    ++with_pose;
  }
  StampedPose last;
  int with_pose = 0;
};

struct SimRun {
  SystemStats stats;
  std::optional<StampedPose> latest;
  LastPoseListener listener;
};

void runSim(const Config& config, SimRun& r, int frames = 60) {
  drivers::sim::SimOptions o;
  o.width = 320;
  o.height = 240;
  o.frames = frames;
  drivers::sim::SimSource source("forward", o);
  System system(config, source.geometricCalibration(), source.photometricCalibration());
  system.setListener(&r.listener);
  EXPECT_FALSE(system.latestPose().has_value());
  drivers::Frame f;
  while (source.next(f)) system.submit({f.image.view(), f.timestamp, f.exposure_ms});
  system.finish();
  r.latest = system.latestPose();
  r.stats = system.stats();
}

TEST(SystemPipeline, LatestPoseIsTheLastTrackedPoseInBothModes) {
  for (const bool deterministic : {true, false}) {
    Config c;
    c.system.deterministic = deterministic;
    SimRun r;
    runSim(c, r);
    ASSERT_GT(r.listener.with_pose, 20) << deterministic;
    ASSERT_TRUE(r.latest.has_value());
    EXPECT_EQ(r.latest->timestamp, r.listener.last.timestamp);
    EXPECT_EQ(r.latest->pose.translation, r.listener.last.pose.translation);
    EXPECT_EQ(r.latest->pose.rotation.coeffs(), r.listener.last.pose.rotation.coeffs());
    // Latency of every frame that reached the odometry and of every frame with a pose; queue
    // wait only when queued.
    const SystemStats& s = r.stats;
    ASSERT_EQ(s.latency.size(), deterministic ? 2u : 3u);
    const StageTiming& processed = s.latency[s.latency.size() - 2];
    EXPECT_EQ(processed.stage, "submit_to_processed");
    EXPECT_EQ(processed.count, s.frames - s.rejected_frames);
    const StageTiming& total = s.latency.back();
    EXPECT_EQ(total.stage, "submit_to_tracked");
    EXPECT_EQ(total.count, s.tracked_frames);
    EXPECT_LT(total.count, processed.count);  // the initialisation's frames have no pose
    EXPECT_GT(total.mean_ms, 0.0);
    EXPECT_LE(total.p50_ms, total.p99_ms);
    EXPECT_LE(total.p99_ms, total.max_ms);
    EXPECT_GE(processed.max_ms, total.max_ms);
    if (!deterministic) {
      EXPECT_EQ(s.latency[0].stage, "queue_wait");
      EXPECT_LE(s.latency[0].mean_ms, processed.mean_ms);  // over the same frames
      EXPECT_EQ(s.submitted_frames, 60);
      EXPECT_EQ(s.dropped_frames, 0);
      EXPECT_GE(s.max_mapping_backlog, 0);
      EXPECT_EQ(s.mapping_backlog, 0);  // finished
    } else {
      EXPECT_EQ(s.queue_capacity, 0);
      EXPECT_EQ(s.max_mapping_backlog, 0);
    }
  }
}

#if defined(__linux__)
/// The CPUs the calling thread may run on.
std::vector<int> allowedCpus() {
  cpu_set_t set;
  CPU_ZERO(&set);
  pthread_getaffinity_np(pthread_self(), sizeof(set), &set);
  std::vector<int> cpus;
  for (int c = 0; c < CPU_SETSIZE; ++c)
    if (CPU_ISSET(c, &set)) cpus.push_back(c);
  return cpus;
}

/// Records the CPU affinity of the tracking thread (onFrame) and the mapping thread
/// (onKeyframe, threaded mode).
class AffinityListener : public SystemListener {
 public:
  void onFrame(const FrameEvent&) override { tracking = allowedCpus(); }
  void onKeyframe(const KeyframeEvent& e) override {
    if (e.keyframe_id >= 2) mapping = allowedCpus();  // the first two come from tracking
  }
  std::vector<int> tracking, mapping;
};

TEST(SystemPipeline, ThreadsArePinnedToTheConfiguredCpus) {
  const std::vector<int> mine = allowedCpus();
  ASSERT_FALSE(mine.empty());
  const int cpu = mine.back();
  Config c;
  c.system.tracking_cpu = cpu;
  c.system.mapping_cpu = cpu;
  drivers::sim::SimOptions o;
  o.width = 320;
  o.height = 240;
  o.frames = 60;
  drivers::sim::SimSource source("forward", o);
  System system(c, source.geometricCalibration(), source.photometricCalibration());
  AffinityListener listener;
  system.setListener(&listener);
  drivers::Frame f;
  while (source.next(f)) system.submit({f.image.view(), f.timestamp, f.exposure_ms});
  system.finish();
  EXPECT_EQ(listener.tracking, std::vector<int>{cpu});
  ASSERT_FALSE(listener.mapping.empty()) << "no keyframe from the mapping thread";
  EXPECT_EQ(listener.mapping, std::vector<int>{cpu});
  EXPECT_EQ(allowedCpus(), mine);  // the caller's thread is left alone
}

TEST(SystemPipeline, RefusedAffinityIsLoggedAndTheSystemStillRuns) {
  Config c;
  c.system.tracking_cpu = 1023;  // no such CPU here: the kernel refuses (EINVAL)
  c.system.mapping_cpu = 1023;
  System system(c, smallCamera());
  BlockingListener listener;
  listener.released = true;
  system.setListener(&listener);
  const ImageU8 img = texturedImage(160, 120);
  for (int i = 0; i < 3; ++i) system.submit({img.view(), 0.1 * i});
  system.finish();
  EXPECT_EQ(system.stats().frames, 3);
}
#endif

std::string configErrorOf(const Config& c) {
  try {
    System system(c, smallCamera());
  } catch (const ConfigError& e) {
    return e.what();
  }
  return {};
}

TEST(SystemPipeline, PipelineSettingsAreValidatedNamingFieldAndRange) {
  Config c;
  c.system.frame_pool_size = 3;
  std::string e = configErrorOf(c);
  EXPECT_NE(e.find("system.frame_pool_size = 3"), std::string::npos) << e;
  EXPECT_NE(e.find("[4, 1024]"), std::string::npos) << e;

  c = Config{};
  c.system.tracking_cpu = -2;
  c.system.mapping_cpu = 1024;
  e = configErrorOf(c);
  EXPECT_NE(e.find("system.tracking_cpu = -2"), std::string::npos) << e;
  EXPECT_NE(e.find("system.mapping_cpu = 1024"), std::string::npos) << e;
  EXPECT_NE(e.find("[-1, 1023]"), std::string::npos) << e;

  c = Config{};
  c.system.live = true;
  c.system.deterministic = true;
  e = configErrorOf(c);
  EXPECT_NE(e.find("system.live"), std::string::npos) << e;
  EXPECT_NE(e.find("system.deterministic"), std::string::npos) << e;
}

TEST(SystemPipeline, PipelineSettingsLoadFromYaml) {
  const Config c = drivers::parseConfigYaml(
      "system:\n  live: true\n  frame_pool_size: 10\n  tracking_cpu: 1\n  mapping_cpu: 0\n",
      "test.yaml");
  EXPECT_TRUE(c.system.live);
  EXPECT_EQ(c.system.frame_pool_size, 10);
  EXPECT_EQ(c.system.tracking_cpu, 1);
  EXPECT_EQ(c.system.mapping_cpu, 0);
  try {
    drivers::parseConfigYaml("system:\n  frame_pool_size: 2\n", "bad.yaml");
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("bad.yaml:2"), std::string::npos) << what;
    EXPECT_NE(what.find("system.frame_pool_size"), std::string::npos) << what;
  }
  const Config defaults;
  EXPECT_FALSE(defaults.system.live);
  EXPECT_EQ(defaults.system.frame_pool_size, 6);
  EXPECT_EQ(defaults.system.tracking_cpu, -1);
  EXPECT_EQ(defaults.system.mapping_cpu, -1);
}

}  // namespace
}  // namespace ldsm
