// The mapping stage on a small synthetic window: one code path in both modes (inline and on its
// own thread give the same map), what it publishes after each job (tracking reference, snapshot,
// events, the map store), and a reset.
#include "pipeline/mapping_stage.h"
#include "pipeline/stage_settings.h"

#include <gtest/gtest.h>

#include <thread>
#include <vector>

#include "synthetic_window.h"

namespace ldsm {
namespace {

using test::SyntheticWindow;

class RecordingListener : public SystemListener {
 public:
  void onKeyframe(const KeyframeEvent& e) override {
    keyframes.push_back(e.keyframe_id);
    threads.push_back(std::this_thread::get_id());
  }
  void onInitialized(const InitializedEvent& e) override { initialized.push_back(e.points); }
  std::vector<int> keyframes;
  std::vector<int> initialized;
  std::vector<std::thread::id> threads;
};

Config stageConfig() {
  Config c;
  c.calibration.refine_radial = false;
  c.loop.enabled = false;
  return c;
}

MappingJob initJob(SyntheticWindow& w) {
  MappingJob job;
  job.kind = MappingJob::Kind::kInitialize;
  job.initialization = w.initialization(2);
  job.reference_pyramid = w.pyramid(0);
  job.reference_info = {0, 0.0, 1.0, w.T_c_w(0), AffineLight{}, {}};
  job.pyramid = w.pyramid(2);
  job.info = {2, 0.2, 1.0, w.T_c_w(2), AffineLight{}, {}};
  return job;
}

MappingJob frameJob(SyntheticWindow& w, int i, bool keyframe) {
  MappingJob job;
  job.kind = keyframe ? MappingJob::Kind::kKeyframe : MappingJob::Kind::kTrace;
  job.pyramid = w.pyramid(i);
  job.info = {i, 0.1 * i, 1.0, w.T_c_w(i), AffineLight{}, {}};
  return job;
}

struct StageRun {
  Trajectory keyframes;
  std::vector<int> keyframe_events;
  std::vector<std::thread::id> event_threads;
  std::int64_t keyframe_count = 0;
  int references = 0;
};

/// Initialises and feeds 18 frames (every third a keyframe), waiting after each job so that the
/// threaded stage never skips a trace.
StageRun runStage(bool inline_mode) {
  SyntheticWindow w(20);
  MapStore store;
  EventSink events;
  RecordingListener listener;
  events.setListener(&listener);
  const Config config = stageConfig();
  MappingStage stage(mappingStageSettings(config, false), w.camera(), w.pool(), store, events,
                     nullptr, inline_mode);
  StageRun run;
  stage.submit(initJob(w));
  stage.waitIdle();
  EXPECT_TRUE(stage.lastInitialization().ok);
  PreparedReference ref;
  run.references += stage.references().takeNewest(ref) ? 1 : 0;
  EXPECT_EQ(ref.keyframe_id, stage.lastInitialization().keyframe_id);
  stage.references().recycle(std::move(ref.tracker));
  for (int i = 3; i < w.frames(); ++i) {
    const bool keyframe = i % 3 == 0;
    if (keyframe) stage.setKeyframeInFlight();
    stage.submit(frameJob(w, i, keyframe));
    stage.waitIdle();
    if (!keyframe) continue;
    EXPECT_FALSE(stage.keyframeInFlight());
    PreparedReference r;
    if (stage.references().takeNewest(r)) {
      ++run.references;
      EXPECT_EQ(r.frame_index, i);
      EXPECT_TRUE(r.tracker->hasReference());
      stage.references().recycle(std::move(r.tracker));
    }
    // The snapshot follows the newest keyframe.
    const std::shared_ptr<const MappingSnapshot> s = stage.snapshot();
    EXPECT_TRUE(s->has_window);
    EXPECT_GT(s->active_point_count, 300);
  }
  stage.finish();
  run.keyframes = store.keyframeTrajectory();
  run.keyframe_events = listener.keyframes;
  run.event_threads = listener.threads;
  run.keyframe_count = stage.keyframes();
  EXPECT_EQ(listener.initialized.size(), 1u);
  return run;
}

TEST(MappingStage, InlineAndThreadedBuildTheSameMap) {
  const StageRun a = runStage(/*inline_mode=*/true);
  const StageRun b = runStage(/*inline_mode=*/false);
  EXPECT_EQ(a.keyframe_count, 2 + 6);
  EXPECT_EQ(b.keyframe_count, a.keyframe_count);
  EXPECT_EQ(a.references, 1 + 6);
  EXPECT_EQ(b.references, a.references);
  EXPECT_EQ(a.keyframe_events, b.keyframe_events);
  ASSERT_EQ(a.keyframes.size(), static_cast<std::size_t>(a.keyframe_count));
  ASSERT_EQ(b.keyframes.size(), a.keyframes.size());
  for (std::size_t k = 0; k < a.keyframes.size(); ++k) {
    EXPECT_EQ(a.keyframes[k].pose.translation, b.keyframes[k].pose.translation) << k;
    EXPECT_EQ(a.keyframes[k].pose.rotation.coeffs(), b.keyframes[k].pose.rotation.coeffs()) << k;
  }
  // Inline: every event on the caller's thread; threaded: all on the one mapping thread.
  for (const std::thread::id& t : a.event_threads) EXPECT_EQ(t, std::this_thread::get_id());
  ASSERT_FALSE(b.event_threads.empty());
  for (const std::thread::id& t : b.event_threads) {
    EXPECT_NE(t, std::this_thread::get_id());
    EXPECT_EQ(t, b.event_threads.front());
  }
}

TEST(MappingStage, ResetEmptiesTheWindowAndDropsTheUnadoptedReference) {
  SyntheticWindow w(8);
  MapStore store;
  EventSink events;
  MappingStage stage(mappingStageSettings(stageConfig(), false), w.camera(), w.pool(), store,
                     events, nullptr, true);
  stage.submit(initJob(w));
  ASSERT_TRUE(stage.lastInitialization().ok);
  stage.setKeyframeInFlight();
  stage.submit(frameJob(w, 4, true));
  MappingJob reset;
  reset.kind = MappingJob::Kind::kReset;
  stage.submit(std::move(reset));
  EXPECT_FALSE(stage.snapshot()->has_window);
  EXPECT_FALSE(stage.keyframeInFlight());
  PreparedReference r;
  EXPECT_FALSE(stage.references().takeNewest(r));
  // The keyframes keep their last poses in the map store.
  EXPECT_EQ(store.keyframeCount(), 3u);
  // A new map can be started.
  stage.submit(initJob(w));
  EXPECT_TRUE(stage.lastInitialization().ok);
  EXPECT_TRUE(stage.references().takeNewest(r));
}

}  // namespace
}  // namespace ldsm
