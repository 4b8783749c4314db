// The mapping stage on a small synthetic window: one code path in both modes (inline and on its
// own thread give the same map), what it publishes after each job (tracking reference, snapshot,
// events, the map store), a reset, loop corrections, relocalisation in the map, map reuse and
// re-anchoring a window that drifted off the map.
#include "pipeline/mapping_stage.h"
#include "pipeline/stage_settings.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <optional>
#include <thread>
#include <vector>

#include "map/map_depth.h"
#include "synthetic_window.h"

namespace ldsm {

/// The stage's private steps the tests drive directly.
struct MappingStageAccess {
  static void applyCorrections(MappingStage& stage,
                               const std::vector<loop::LoopCorrection>& corrections) {
    stage.applyCorrections(corrections);
  }
  static void trackingPoints(const MappingStage& stage, std::vector<DepthPoint>& out) {
    stage.mapper_.trackingPoints(out);
  }
};

namespace {

using test::SyntheticWindow;

class RecordingListener : public SystemListener {
 public:
  void onKeyframe(const KeyframeEvent& e) override {
    keyframes.push_back(e.keyframe_id);
    threads.push_back(std::this_thread::get_id());
  }
  void onInitialized(const InitializedEvent& e) override { initialized.push_back(e.points); }
  void onLoopClosure(const LoopClosureEvent& e) override { loops.push_back(e); }
  void onReuse(const ReuseEvent& e) override { reuse.push_back(e); }
  std::vector<int> keyframes;
  std::vector<int> initialized;
  std::vector<LoopClosureEvent> loops;
  std::vector<ReuseEvent> reuse;
  std::vector<std::thread::id> threads;
};

Config stageConfig() {
  Config c;
  c.calibration.refine_radial = false;
  c.calibration.refine_focal = false;
  c.calibration.refine_principal_point = false;
  c.loop.enabled = false;
  return c;
}

/// stageConfig() with map reuse on and every keyframe that leaves kept in the map.
Config reuseConfig() {
  Config c = stageConfig();
  c.reuse.enabled = true;
  c.reuse.cull_redundant = false;
  return c;
}

MappingJob initJob(SyntheticWindow& w) {
  MappingJob job;
  job.kind = MappingJob::Kind::kInitialize;
  job.initialization = w.initialization(2);
  job.reference_pyramid = w.pyramid(0);
  job.reference_info = {0, 0.0, 1.0, w.T_c_w(0), AffineLight{}};
  job.pyramid = w.pyramid(2);
  job.info = {2, 0.2, 1.0, w.T_c_w(2), AffineLight{}};
  return job;
}

MappingJob frameJob(SyntheticWindow& w, int i, bool keyframe) {
  MappingJob job;
  job.kind = keyframe ? MappingJob::Kind::kKeyframe : MappingJob::Kind::kTrace;
  job.pyramid = w.pyramid(i);
  job.info = {i, 0.1 * i, 1.0, w.T_c_w(i), AffineLight{}};
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

/// An inline stage that has initialised on `w` and taken every third frame up to `last` as a
/// keyframe, so that the first keyframes have left the window for the map store.
struct MappedWindow {
  explicit MappedWindow(int frames, const Config& config)
      : w(frames),
        stage(mappingStageSettings(config, false), w.camera(), w.pool(), store, events, nullptr,
              /*inline_mode=*/true) {
    events.setListener(&listener);
    stage.submit(initJob(w));
    EXPECT_TRUE(stage.lastInitialization().ok);
  }
  void keyframes(int first, int last, int step) {
    for (int i = first; step > 0 ? i <= last : i >= last; i += step) {
      stage.setKeyframeInFlight();
      stage.submit(frameJob(w, i, true));
    }
  }
  /// A keyframe that has left the window.
  int mapKeyframe() const {
    const std::vector<int>& window = stage.snapshot()->window_ids;
    for (int id = 0; id < 100; ++id)
      if (store.hasKeyframe(id) && std::find(window.begin(), window.end(), id) == window.end())
        return id;
    return -1;
  }

  SyntheticWindow w;
  MapStore store;
  EventSink events;
  RecordingListener listener;
  MappingStage stage;
};

TEST(MappingStage, LoopCorrectionsMoveTheMapButNotTheWindow) {
  MappedWindow m(26, stageConfig());
  m.keyframes(3, 24, 3);
  const int old_id = m.mapKeyframe();
  ASSERT_GE(old_id, 0) << "no keyframe left the window";
  const KeyframeRecord before = m.store.keyframe(old_id);
  const std::vector<int> window = m.stage.snapshot()->window_ids;
  ASSERT_FALSE(window.empty());
  const KeyframeRecord newest_before = m.store.keyframe(window.back());

  // Not significant: reported, nothing moves.
  loop::DetectedLoop loop;
  loop.current_keyframe_id = window.back();
  loop.candidate_keyframe_id = old_id;
  loop.inliers = 40;
  loop::LoopCorrection small;
  small.loops.push_back(loop);
  // Significant: the pose graph moved the old keyframe 0.1 m further along x, at scale 1.5.
  loop::LoopCorrection big;
  loop.significant = true;
  big.loops.push_back(loop);
  const Sim3d S_new(before.T_w_c.so3(), before.T_w_c.translation() + Eigen::Vector3d(0.1, 0, 0),
                    1.5);
  big.S_world_camera = {{old_id, S_new}};
  MappingStageAccess::applyCorrections(m.stage, {small, big});

  ASSERT_EQ(m.listener.loops.size(), 2u);
  EXPECT_EQ(m.listener.loops[0].corrected_keyframes, 0);
  EXPECT_EQ(m.listener.loops[1].corrected_keyframes, 1);
  EXPECT_EQ(m.listener.loops[1].matched_keyframe_id, old_id);
  EXPECT_EQ(m.events.loops().size(), 2u) << "kept for the statistics";
  const KeyframeRecord after = m.store.keyframe(old_id);
  EXPECT_LT((after.T_w_c.translation() - S_new.translation()).norm(), 1e-12);
  EXPECT_DOUBLE_EQ(after.scale, 1.5);
  // The window's keyframes keep their poses (the map moves to the window, not the other way).
  const KeyframeRecord newest_after = m.store.keyframe(window.back());
  EXPECT_EQ(newest_after.T_w_c.translation(), newest_before.T_w_c.translation());
  EXPECT_EQ(m.stage.snapshot()->window_ids, window);
  EXPECT_TRUE(m.stage.snapshot()->reactivated.empty());
}

TEST(MappingStage, RelocalizeStartsAWindowAtAMapKeyframe) {
  MappedWindow m(26, reuseConfig());
  m.keyframes(3, 24, 3);
  MappingJob reset;
  reset.kind = MappingJob::Kind::kReset;
  m.stage.submit(std::move(reset));
  ASSERT_FALSE(m.stage.snapshot()->has_window);
  PreparedReference r;
  ASSERT_FALSE(m.stage.references().takeNewest(r));

  // The frame right after keyframe `anchor`'s frame, found in the map at that keyframe.
  int anchor = -1;
  for (int id = 0; id < 100 && anchor < 0; ++id)
    if (m.store.keyframeData(id) && m.store.keyframe(id).frame_index >= 9) anchor = id;
  ASSERT_GE(anchor, 0) << "no keyframe kept for reuse";
  const int frame = static_cast<int>(m.store.keyframe(anchor).frame_index) + 1;
  const std::size_t keyframe_events = m.listener.keyframes.size();
  MappingJob job;
  job.kind = MappingJob::Kind::kRelocalize;
  job.pyramid = m.w.pyramid(frame);
  job.info = {frame, 0.1 * frame, 1.0, m.w.T_c_w(frame), AffineLight{}};
  job.anchor_keyframe = anchor;
  m.stage.submit(std::move(job));

  const InitializationOutcome& outcome = m.stage.lastInitialization();
  ASSERT_TRUE(outcome.ok);
  EXPECT_GT(outcome.points, 100) << "map points in view";
  EXPECT_GT(outcome.keyframe_id, anchor);
  // Published as after an initialisation: reference, snapshot, a keyframe event (and no second
  // initialised event).
  ASSERT_TRUE(m.stage.references().takeNewest(r));
  EXPECT_EQ(r.keyframe_id, outcome.keyframe_id);
  EXPECT_TRUE(m.stage.snapshot()->has_window);
  ASSERT_EQ(m.listener.keyframes.size(), keyframe_events + 1);
  EXPECT_EQ(m.listener.keyframes.back(), outcome.keyframe_id);
  EXPECT_EQ(m.listener.initialized.size(), 1u);
  EXPECT_EQ(m.stage.snapshot()->reuse.reactivations, 1);
  EXPECT_LT(test::poseError(outcome.T_c_w, m.w.T_c_w(frame))[1], 0.05);
}

TEST(MappingStage, ALoadedMapGivesRelocalisationItsMedianDepthBeforeAnyWindow) {
  // A map of the wall-and-floor scene (4 units away), saved and loaded into a new stage.
  MappedWindow m(26, reuseConfig());
  m.keyframes(3, 24, 3);
  const StoredMap saved = m.store.firstMap();
  const std::optional<double> depth = medianKeyframeDepth(saved);
  ASSERT_TRUE(depth.has_value());
  // The window's own measure of the same scene, and the truth's range.
  EXPECT_NEAR(*depth, m.stage.snapshot()->median_depth, 0.25 * m.stage.snapshot()->median_depth);
  EXPECT_GT(*depth, 2.0);
  EXPECT_LT(*depth, 5.0);

  MapStore store;
  store.loadMap(saved);
  EventSink events;
  MappingStage stage(mappingStageSettings(reuseConfig(), false), m.w.camera(), m.w.pool(), store,
                     events, nullptr, /*inline_mode=*/true);
  EXPECT_EQ(stage.snapshot()->median_depth, 1.0) << "the default before anything is known";
  stage.continueAfterLoadedMap(100, MapCalibration{}, depth);
  EXPECT_FALSE(stage.snapshot()->has_window);
  EXPECT_EQ(stage.snapshot()->median_depth, *depth);
  // A map without points (or a depth that is no depth) keeps what the stage had.
  stage.continueAfterLoadedMap(100, MapCalibration{}, std::nullopt);
  EXPECT_EQ(stage.snapshot()->median_depth, *depth);
  stage.continueAfterLoadedMap(100, MapCalibration{}, std::numeric_limits<double>::quiet_NaN());
  EXPECT_EQ(stage.snapshot()->median_depth, *depth);
}

TEST(MappingStage, ReturningCameraBringsMapKeyframesBack) {
  Config config = reuseConfig();
  config.reuse.min_keyframe_age = 2;
  MappedWindow m(34, config);
  m.keyframes(3, 33, 3);   // out ...
  m.keyframes(32, 2, -3);  // ... and back over the first keyframes
  ASSERT_FALSE(m.listener.reuse.empty()) << "no map keyframe brought back";
  for (const ReuseEvent& e : m.listener.reuse) {
    EXPECT_FALSE(e.reactivated.empty());
    for (const int id : e.reactivated) EXPECT_LT(id, e.keyframe_id);
  }
  EXPECT_GT(m.stage.snapshot()->reuse.reactivations, 0);
}

/// Moves every keyframe of the map store that is not the window's own by `shift` (world
/// coordinates), as a correction would: the map under the window moves, the window does not.
/// With `keep_held`, the map keyframes the window holds stay where they are (a map that
/// disagrees with itself).
void shiftTheMap(MappedWindow& m, const Eigen::Vector3d& shift, bool keep_held) {
  std::vector<int> keep = m.stage.snapshot()->window_ids;
  if (keep_held)
    for (const int id : m.stage.snapshot()->reactivated) keep.push_back(id);
  loop::LoopCorrection c;
  for (int id = 0; id < 100; ++id) {
    if (!m.store.hasKeyframe(id) || std::find(keep.begin(), keep.end(), id) != keep.end()) continue;
    const KeyframeRecord k = m.store.keyframe(id);
    c.S_world_camera[id] = Sim3d(k.T_w_c.so3(), k.T_w_c.translation() + shift, k.scale);
  }
  ASSERT_GE(c.S_world_camera.size(), 3u);
  MappingStageAccess::applyCorrections(m.stage, {c});
}

/// What driftOffTheMapAndBack saw.
struct DriftRun {
  bool requested = false;   ///< a re-anchoring was requested
  ReanchorRequest request;  ///< the first one
  SE3d T_newest_w_truth;    ///< the true pose of the keyframe it was requested at
  ReuseStats stats;
};

/// Out and back, with the map moved under the window on the way back (by `shift`) once the
/// window is on it: the first re-anchoring requested, if any.
DriftRun driftOffTheMapAndBack(const Eigen::Vector3d& shift, bool keep_held = false) {
  Config config = reuseConfig();
  config.reuse.min_keyframe_age = 2;
  MappedWindow m(34, config);
  m.keyframes(3, 33, 3);
  int i = 32;
  for (; i >= 2 && m.stage.snapshot()->reactivated.empty(); i -= 3) m.keyframes(i, i, -3);
  EXPECT_FALSE(m.stage.snapshot()->reactivated.empty()) << "never back on the map";
  if (shift.norm() > 0) shiftTheMap(m, shift, keep_held);
  DriftRun run;
  for (; i >= 2 && !run.requested; i -= 3) {
    m.keyframes(i, i, -3);
    run.requested = m.stage.takeReanchorRequest(run.request);
    run.T_newest_w_truth = m.w.T_c_w(i);
  }
  run.stats = m.stage.snapshot()->reuse;
  return run;
}

TEST(MappingStage, AWindowThatDriftedOffTheMapIsPutBackOnIt) {
  // The map keyframe brought back is moved with the map and no longer fits; those found next fit
  // the newest keyframe, but several pixels off its pose (15 cm at the 4 m wall is 10 px; the
  // window, pulled part of the way by the moved map keyframe, is nearer): beyond the
  // optimisation's reach. They agree on where it is in the map, and the stage asks for a new
  // window there.
  const Eigen::Vector3d shift(0.15, 0.0, 0.0);
  const DriftRun run = driftOffTheMapAndBack(shift);
  ASSERT_TRUE(run.requested);
  EXPECT_EQ(run.stats.window_reanchors, 1);
  EXPECT_GE(run.request.anchor_keyframe, 0);
  // The map's world is the true world moved by `shift` (the map was made on the true poses):
  // T_c_w(map) = T_c_w(truth) * shift^-1.
  const SE3d truth_in_map = run.T_newest_w_truth * SE3d(Eigen::Matrix3d::Identity(), -shift);
  const Eigen::Vector2d error = test::poseError(run.request.T_newest_w_map, truth_in_map);
  const Eigen::Vector2d drift = test::poseError(run.request.T_newest_w_window, truth_in_map);
  EXPECT_LT(error[1], 0.01) << "translation error (m), drift " << drift[1];
  EXPECT_LT(error[0], 0.002) << "rotation error (rad), drift " << drift[0];
  EXPECT_GT(drift[1], 0.05);
}

TEST(MappingStage, AWindowHoldingAMapKeyframeThatFitsIsNotReanchored) {
  // A like move (9 cm), but the map keyframe the window holds stays: it keeps fitting, and the
  // others, which put the window 4-7 px away, measure the map's own disagreement, not the
  // window's drift.
  const DriftRun run = driftOffTheMapAndBack(Eigen::Vector3d(0.09, 0.0, 0.0), true);
  EXPECT_FALSE(run.requested);
  EXPECT_EQ(run.stats.window_reanchors, 0);
}

TEST(MappingStage, AWindowOnTheMapIsNotReanchored) {
  const DriftRun run = driftOffTheMapAndBack(Eigen::Vector3d::Zero());
  EXPECT_FALSE(run.requested);
  EXPECT_EQ(run.stats.window_reanchors, 0);
  EXPECT_GT(run.stats.reactivations, 1);
}

/// Map points in the window's tracking points (those of map keyframes in the window that the
/// window has verified).
int mapPointsInView(const MappingStage& stage) {
  std::vector<DepthPoint> all;
  MappingStageAccess::trackingPoints(stage, all);
  return static_cast<int>(
      std::count_if(all.begin(), all.end(), [](const DepthPoint& p) { return p.from_map; }));
}

/// From keyframe `first` back towards the start until map keyframes' points are in the window's
/// tracking points.
void backOnTheMap(MappedWindow& m, int first = 32) {
  for (int i = first; i >= 2 && mapPointsInView(m.stage) == 0; i -= 3) m.keyframes(i, i, -3);
}

TEST(MappingStage, TheReferencePointRatioBoundsThePublishedReference) {
  // The same map with and without a budget (the frames' poses are given: the reference does not
  // change the window), so the published references differ only by the budget
  // (reference_budget.h; its rule is tested in reference_budget_test.cpp).
  struct Published {
    int level0 = 0;                 ///< level-0 points of the published reference
    std::vector<DepthPoint> input;  ///< the window's tracking points before the budget
  };
  const int active_points = Config{}.window.active_points;
  const auto publish = [](double ratio) {
    Config config = reuseConfig();
    config.reuse.min_keyframe_age = 2;
    config.reuse.reference_point_ratio = ratio;
    MappedWindow m(34, config);
    m.keyframes(3, 33, 3);
    backOnTheMap(m);
    Published out;
    PreparedReference r;
    EXPECT_TRUE(m.stage.references().takeNewest(r));
    if (r.tracker) out.level0 = r.tracker->depthMaps().points(0).count;
    MappingStageAccess::trackingPoints(m.stage, out.input);
    return out;
  };
  const Published unlimited = publish(0.0);
  int map_points = 0;
  for (const DepthPoint& p : unlimited.input) map_points += p.from_map ? 1 : 0;
  ASSERT_GT(map_points, 50);
  ASSERT_GT(unlimited.input.size(), static_cast<std::size_t>(map_points) + 50);

  // A budget of the map points alone: the window's own points are left out of the reference.
  const Published bounded = publish(map_points / static_cast<double>(active_points));
  ASSERT_EQ(bounded.input.size(), unlimited.input.size()) << "the window itself changed";
  EXPECT_LT(bounded.level0, unlimited.level0);
  // A budget above every point changes nothing.
  const Published roomy = publish((unlimited.input.size() + 1.0) / active_points);
  EXPECT_EQ(roomy.level0, unlimited.level0);
}

TEST(MappingStage, MapKeyframesCarryTheDescriptorsOfTheirOwnImageAndCorners) {
  // With reuse on, a keyframe is described when it is made (for the search) and that description
  // is kept for when it leaves the window: it must be what describing it then would give.
  MappedWindow m(26, reuseConfig());
  m.keyframes(3, 24, 3);
  OrbExtractor orb(SyntheticWindow::kW, SyntheticWindow::kH);
  std::vector<OrbDescriptor> descriptors;
  std::vector<std::uint32_t> kept;
  int checked = 0;
  for (int id = 0; id < 100; ++id) {
    const std::shared_ptr<const MarginalizedKeyframe> kf = m.store.keyframeData(id);
    if (!kf) continue;
    ASSERT_FALSE(kf->corners.empty()) << "keyframe " << id;
    ASSERT_EQ(kf->descriptors.size(), kf->corners.size()) << "keyframe " << id;
    orb.compute(m.w.pyramid(static_cast<int>(kf->frame_index))->gradients(0), kf->corners,
                descriptors, kept);
    ASSERT_EQ(kept.size(), kf->corners.size()) << "keyframe " << id;
    EXPECT_TRUE(descriptors == kf->descriptors) << "keyframe " << id;
    ++checked;
  }
  EXPECT_GE(checked, 3);
}

}  // namespace
}  // namespace ldsm
