// The loop closer's pose graph as LDSM builds it: odometry edges measured in one state of the
// window, constraints from map keyframes brought back into the window (map reuse), a pose graph
// deferred until no new significant constraint arrived for a few keyframes, and candidates that
// are connected to the query through shared points are no loops.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <vector>

#include "ldsm/config.h"
#include "loop/loop_closer.h"
#include "synthetic_keyframes.h"

namespace ldsm::loop {
namespace {

// Ground truth: n keyframes around a circle of radius 1 (the camera looking along the tangent);
// keyframe n is back at keyframe 0's place.
SE3d truePose(int k, int n) {
  const double a = 2.0 * M_PI * k / n;
  return SE3d(SO3d::exp(Eigen::Vector3d(0, -a, 0)), Eigen::Vector3d(std::sin(a), 0, std::cos(a)));
}

// The window's estimate of the chain: every step with a small yaw error and 1 % too long.
SE3d driftedStep(const SE3d& step) {
  const SE3d longer(step.so3(), 1.01 * step.translation());
  return longer * SE3d(SO3d::exp(Eigen::Vector3d(0, 0.004, 0)), Eigen::Vector3d::Zero());
}

LoopJob keyframe(int id, const SE3d& T_w_c) {
  LoopJob job;
  job.id = id;
  job.frame_index = 10 * id;
  job.timestamp = 0.1 * id;
  job.T_w_c = T_w_c;
  return job;
}

// The keyframe's corners: those of `f`, or (null) 300 random ones that match nothing.
void describe(LoopJob& job, const KeyframeFeatures* f, test::SceneRandom& rnd) {
  if (f) {
    job.corners = f->pixels;
    job.corner_idepth = f->idepth;
    job.descriptors = f->descriptors;
    return;
  }
  for (int i = 0; i < 300; ++i) {
    job.corners.emplace_back(static_cast<float>(rnd.uniform(0, 639)),
                             static_cast<float>(rnd.uniform(0, 479)));
    job.corner_idepth.push_back(0.25f);
    job.descriptors.push_back(rnd.descriptor());
  }
}

KeyframeLink link(int other, const SE3d& T_w_this, const SE3d& T_w_other, bool map_keyframe,
                  int shared = 200) {
  KeyframeLink l;
  l.other = other;
  l.T_this_other = T_w_this.inverse() * T_w_other;
  l.shared_points = shared;
  l.map_keyframe = map_keyframe;
  return l;
}

LoopConfig config() {
  LoopConfig c;
  c.pose_graph_delay_keyframes = 5;
  c.pose_graph_max_delay_keyframes = 20;
  return c;
}

struct Revisit {
  std::vector<SE3d> truth;    ///< by keyframe id
  std::vector<SE3d> drifted;  ///< the window's poses as the keyframes left it
  std::vector<LoopCorrection> corrections;
  int first_correction_after = -1;  ///< keyframes handed over when the first correction came
};

// A camera that goes once around the circle with the drifting odometry; at keyframe n the window
// brings map keyframe 0 back (map reuse) and snaps onto it, and the camera goes on along the
// second lap with exact poses. Keyframes leave the window one keyframe after they were made; the
// first `linked` of them from keyframe n on held map keyframe 0 in their window.
Revisit driveRevisit(int n, int extra, bool reuse_link, int linked = 3,
                     const LoopConfig& c = config()) {
  LoopCloser closer(c, test::testCamera(500.0), /*inline_mode=*/true);
  Revisit r;
  SE3d est = truePose(0, n);
  for (int k = 0; k <= n + extra; ++k) {
    r.truth.push_back(truePose(k, n));
    if (k > 0) {
      const SE3d step = truePose(k - 1, n).inverse() * truePose(k, n);
      est = est * (k <= n ? driftedStep(step) : step);
    }
    r.drifted.push_back(est);
  }
  // From keyframe n on the window has snapped onto the map: its poses are the true ones.
  std::vector<SE3d> window = r.drifted;
  for (int k = n; k <= n + extra; ++k) window[k] = r.truth[k];
  for (int k = 0; k <= n + extra; ++k) {
    // Keyframe k leaves the window; keyframe k + 1 was in it, with the pose the window had then:
    // the drifted one up to keyframe n (the snap comes with keyframe n's own optimisation).
    LoopJob job = keyframe(k, window[k]);
    if (k < n + extra) {
      const SE3d next = k + 1 == n ? r.drifted[n] : window[k + 1];
      job.links.push_back(link(k + 1, window[k], next, false));
    }
    if (reuse_link && k >= n && k < n + linked)
      job.links.push_back(link(0, window[k], r.truth[0], true));
    closer.keyframeLeftWindow(std::move(job));
    for (LoopCorrection& corr : closer.takeCorrections()) {
      if (r.corrections.empty()) r.first_correction_after = k + 1;
      r.corrections.push_back(std::move(corr));
    }
  }
  closer.flush();
  for (LoopCorrection& corr : closer.takeCorrections()) r.corrections.push_back(std::move(corr));
  return r;
}

double meanPositionError(const std::map<int, Sim3d>& poses, const std::vector<SE3d>& truth,
                         int first, int last) {
  double sum = 0.0;
  for (int k = first; k <= last; ++k)
    sum += (poses.at(k).translation() - truth[k].translation()).norm();
  return sum / (last - first + 1);
}

// Measured: the drifted lap ends 0.17 m from where it began (0.4 % yaw, 1 % scale per step); the
// constraint to map keyframe 0 shows it (odometry chi2 in the thousands), and the deferred pose
// graph spreads it: the lap's keyframes come within a few millimetres of the truth.
TEST(LoopCloser, ReuseConstraintSpreadsTheRevealedDriftAfterTheDelay) {
  const int n = 30, extra = 10;
  const Revisit r = driveRevisit(n, extra, true);
  ASSERT_FALSE(r.corrections.empty()) << "the revisit's drift was never corrected";
  const LoopCorrection& c = r.corrections.front();
  EXPECT_GE(c.reuse_constraints, 1);
  EXPECT_TRUE(c.loops.empty());
  // Deferred: the constraint came with keyframe n; the graph ran only once no new significant
  // constraint had arrived for pose_graph_delay_keyframes keyframes.
  EXPECT_GE(r.first_correction_after, n + 1 + config().pose_graph_delay_keyframes);
  EXPECT_LE(r.first_correction_after, n + 1 + config().pose_graph_max_delay_keyframes);
  std::map<int, Sim3d> drifted;
  for (int k = 0; k <= n; ++k) drifted[k] = Sim3d(r.drifted[k]);
  const double before = meanPositionError(drifted, r.truth, 1, n - 1);
  const double after = meanPositionError(c.S_world_camera, r.truth, 1, n - 1);
  std::printf("mean position error of the lap: %.4f drifted, %.4f corrected\n", before, after);
  EXPECT_GT(before, 0.05);
  EXPECT_LT(after, 0.25 * before);
  // The keyframes after the snap were right already and stay (the newest is held fixed).
  EXPECT_LT((c.S_world_camera.at(n).translation() - r.truth[n].translation()).norm(), 0.01);
}

// The window held map keyframe 0 up to the correction: the window's optimisation measured where it
// lies, so the correction leaves it there (LoopConfig::hold_reused_keyframes) and moves the lap
// between. Let free, the pose graph moves it a little towards the drifted odometry chain, and
// the window would hold map points that no longer fit its images.
TEST(LoopCloser, CorrectionKeepsTheMapKeyframesTheWindowHolds) {
  const int n = 30, extra = 10;
  for (const bool hold : {true, false}) {
    LoopConfig c = config();
    c.hold_reused_keyframes = hold;
    const Revisit r = driveRevisit(n, extra, true, extra + 1, c);
    ASSERT_FALSE(r.corrections.empty());
    const LoopCorrection& first = r.corrections.front();
    const Sim3d& held = first.S_world_camera.at(0);
    const double moved = (held.translation() - r.truth[0].translation()).norm();
    const double turned = (held.so3().inverse() * r.truth[0].so3()).log().norm();
    std::printf("hold %d: map keyframe 0 moved %.2e m, turned %.2e rad, scale %.6f\n", hold, moved,
                turned, held.scale());
    if (hold) {
      EXPECT_LT(moved, 1e-9);
      EXPECT_LT(turned, 1e-9);
      EXPECT_NEAR(held.scale(), 1.0, 1e-9);
    } else {
      EXPECT_GT(moved + turned, 1e-4) << "the case the hold is for: a free vertex 0 moves";
    }
    // Either way the lap's drift is spread.
    std::map<int, Sim3d> drifted;
    for (int k = 0; k <= n; ++k) drifted[k] = Sim3d(r.drifted[k]);
    EXPECT_LT(meanPositionError(first.S_world_camera, r.truth, 1, n - 1),
              0.25 * meanPositionError(drifted, r.truth, 1, n - 1));
  }
}

TEST(LoopCloser, WithoutTheMapConstraintNothingIsCorrected) {
  const Revisit r = driveRevisit(30, 10, false);
  EXPECT_TRUE(r.corrections.empty());
}

// A map keyframe that agrees with the chain (no drift) triggers nothing.
TEST(LoopCloser, ConsistentReuseConstraintCorrectsNothing) {
  LoopCloser closer(config(), test::testCamera(500.0), true);
  const int n = 30;
  for (int k = 0; k <= n + 10; ++k) {
    LoopJob job = keyframe(k, truePose(k, n));
    job.links.push_back(link(k + 1, truePose(k, n), truePose(k + 1, n), false));
    if (k >= n && k < n + 3) job.links.push_back(link(0, truePose(k, n), truePose(0, n), true));
    closer.keyframeLeftWindow(std::move(job));
  }
  closer.flush();
  EXPECT_TRUE(closer.takeCorrections().empty());
}

// loop.exclude_recent_keyframes = n: the n keyframes right before the query are never its loop
// candidates (the keyframe n + 1 back is).
TEST(LoopCloser, TheRecentKeyframesAreNoLoopCandidates) {
  test::SceneOptions o;
  o.S_current_candidate =
      Sim3d(SO3d::exp(Eigen::Vector3d(0.02, -0.05, 0.03)), Eigen::Vector3d(0.1, -0.05, 0.08), 1.0);
  const test::KeyframePair pair = test::makeKeyframePair(o);
  constexpr int kRecent = 8, kCandidate = 3;
  auto loopsAt = [&](int current_id) {
    LoopConfig c = config();
    c.exclude_recent_keyframes = kRecent;
    LoopCloser closer(c, pair.current.camera, true);
    test::SceneRandom rnd(7);
    for (int k = 0; k <= current_id; ++k) {
      LoopJob job = keyframe(k, SE3d(SO3d(), Eigen::Vector3d(0.05 * k, 0, 0)));
      const KeyframeFeatures* f = k == kCandidate   ? &pair.candidate
                                  : k == current_id ? &pair.current
                                                    : nullptr;
      describe(job, f, rnd);
      closer.keyframeLeftWindow(std::move(job));
    }
    closer.flush();
    int loops = 0;
    for (const LoopCorrection& corr : closer.takeCorrections())
      for (const DetectedLoop& l : corr.loops)
        if (l.current_keyframe_id == current_id && l.candidate_keyframe_id == kCandidate) ++loops;
    return loops;
  };
  EXPECT_EQ(loopsAt(kCandidate + kRecent + 1), 1);
  EXPECT_EQ(loopsAt(kCandidate + kRecent), 0);
}

// A revisit seen by `points` corners, every one matched with depth at its true pixel.
test::KeyframePair fewCornersRevisit(int points) {
  test::SceneOptions o;
  o.num_points = points;
  o.current_depth_fraction = 1.0;
  o.candidate_depth_fraction = 1.0;
  o.wrong_pixel_fraction = 0.0;
  o.extra_outliers = 0;
  o.S_current_candidate =
      Sim3d(SO3d::exp(Eigen::Vector3d(0.02, -0.05, 0.03)), Eigen::Vector3d(0.1, -0.05, 0.08), 1.0);
  return test::makeKeyframePair(o);
}

// loop.min_matches and loop.min_pnp_inliers reach the verification: 20-29 matched corners are
// below the default 30 matches, 12-19 below the default 20 PnP inliers (and matches with depth,
// which follow them); each revisit is accepted only when the configuration asks for few enough.
TEST(LoopCloser, MatchAndPnpThresholdsComeFromTheConfiguration) {
  LoopConfig c;
  c.min_matches = 40;
  c.min_pnp_inliers = 25;
  c.min_inliers = 15;
  const LoopVerificationSettings mapped = loopVerificationSettings(c);
  EXPECT_EQ(mapped.min_matches, 40);
  EXPECT_EQ(mapped.min_matches_with_depth, 25);
  EXPECT_EQ(mapped.pnp.min_inliers, 25);
  EXPECT_EQ(mapped.min_inliers, 15);

  c = LoopConfig();
  const auto verify = [&](const test::KeyframePair& p) {
    return verifyLoop(p.current, p.candidate, loopVerificationSettings(c));
  };
  const test::KeyframePair p26 = fewCornersRevisit(26);
  ASSERT_GE(p26.num_true, 20);
  ASSERT_LT(p26.num_true, 30);
  EXPECT_NE(verify(p26).reason.find("(need 30)"), std::string::npos) << verify(p26).reason;
  c.min_matches = 20;
  EXPECT_TRUE(verify(p26).accepted) << verify(p26).reason;

  const test::KeyframePair p16 = fewCornersRevisit(16);
  ASSERT_GE(p16.num_true, 12);
  ASSERT_LT(p16.num_true, 20);
  c.min_matches = 12;
  c.min_inliers = 12;
  c.min_pnp_inliers = p16.num_true + 1;  // more than the revisit's correspondences with depth
  EXPECT_FALSE(verify(p16).accepted);
  c.min_pnp_inliers = 12;
  EXPECT_TRUE(verify(p16).accepted) << verify(p16).reason;
}

// A keyframe that shares many points with another (through the window or a map keyframe brought
// back) is connected to it already: it is no loop candidate, however alike the two look.
TEST(LoopCloser, CovisibleKeyframesAreNoLoopCandidates) {
  test::SceneOptions o;
  o.S_current_candidate =
      Sim3d(SO3d::exp(Eigen::Vector3d(0.02, -0.05, 0.03)), Eigen::Vector3d(0.1, -0.05, 0.08), 1.0);
  const test::KeyframePair pair = test::makeKeyframePair(o);
  auto run = [&](int shared) {
    LoopConfig c = config();
    c.exclude_recent_keyframes = 5;
    LoopCloser closer(c, pair.current.camera, true);
    test::SceneRandom rnd(7);
    const int candidate_id = 3, current_id = 40;
    int loops = 0;
    for (int k = 0; k <= current_id; ++k) {
      LoopJob job = keyframe(k, SE3d(SO3d(), Eigen::Vector3d(0.05 * k, 0, 0)));
      const KeyframeFeatures* f = k == candidate_id ? &pair.candidate
                                  : k == current_id ? &pair.current
                                                    : nullptr;
      describe(job, f, rnd);
      if (k == current_id) {
        const SE3d T_w_cand(SO3d(), Eigen::Vector3d(0.05 * candidate_id, 0, 0));
        // A window link (a map keyframe held in the window would also tie the two poses, and
        // this loop, which disagrees with them, would be rejected for that).
        job.links.push_back(link(candidate_id, job.T_w_c, T_w_cand, false, shared));
      }
      closer.keyframeLeftWindow(std::move(job));
    }
    closer.flush();
    for (const LoopCorrection& corr : closer.takeCorrections())
      for (const DetectedLoop& l : corr.loops)
        if (l.current_keyframe_id == current_id && l.candidate_keyframe_id == candidate_id) ++loops;
    return loops;
  };
  EXPECT_EQ(run(20), 1) << "the pair must be a verifiable loop for this test to mean anything";
  EXPECT_EQ(run(150), 0);
}

// A keyframe whose window held a map keyframe (reuse) was aligned to the map there: between it
// and a keyframe that shared a window with that map keyframe no drift can have built up. A loop
// to such a keyframe that disagrees with where the map puts it is a wrong measurement, not drift
// to correct. The same loop without the held keyframe (drift over the whole chain), or with a
// held keyframe far from the candidate along the chain, is a correction.
TEST(LoopCloser, LoopDisagreeingWithTheHeldMapKeyframeIsRejected) {
  test::SceneOptions o;
  o.S_current_candidate =
      Sim3d(SO3d::exp(Eigen::Vector3d(0.02, -0.05, 0.03)), Eigen::Vector3d(0.1, -0.05, 0.08), 1.0);
  const test::KeyframePair pair = test::makeKeyframePair(o);
  struct Result {
    int loops = 0;
    bool significant = false;
    double chi2 = 0.0;
  };
  const int candidate_id = 3, current_id = 40;
  auto run = [&](int held_id, double offset) {
    const bool hold = held_id >= 0;
    LoopConfig c = config();
    c.exclude_recent_keyframes = 5;
    LoopCloser closer(c, pair.current.camera, true);
    test::SceneRandom rnd(7);
    auto chainPose = [](int k) { return SE3d(SO3d(), Eigen::Vector3d(0.05 * k, 0, 0)); };
    // Where the graph puts the current keyframe: as the loop measures it, plus `offset`.
    const SE3d T_w_cand = chainPose(candidate_id);
    const SE3d T_w_cur =
        SE3d(SO3d(), Eigen::Vector3d(offset, 0, 0)) * T_w_cand *
        SE3d(pair.S_current_candidate.so3(), pair.S_current_candidate.translation()).inverse();
    Result r;
    for (int k = 0; k <= current_id; ++k) {
      LoopJob job = keyframe(k, k == current_id ? T_w_cur : chainPose(k));
      const KeyframeFeatures* f = k == candidate_id ? &pair.candidate
                                  : k == current_id ? &pair.current
                                                    : nullptr;
      describe(job, f, rnd);
      // The chain's keyframes shared a window with their successors.
      if (k + 1 < current_id) job.links.push_back(link(k + 1, job.T_w_c, chainPose(k + 1), false));
      if (k == current_id && hold)
        job.links.push_back(link(held_id, job.T_w_c, chainPose(held_id), true, 20));
      closer.keyframeLeftWindow(std::move(job));
    }
    closer.flush();
    for (const LoopCorrection& corr : closer.takeCorrections())
      for (const DetectedLoop& l : corr.loops)
        if (l.current_keyframe_id == current_id && l.candidate_keyframe_id == candidate_id) {
          ++r.loops;
          r.significant = l.significant;
          r.chi2 = l.drift_chi2;
        }
    std::printf("held %d, offset %.2f m: %d loop(s), chi2 %.1f%s\n", held_id, offset, r.loops,
                r.chi2, r.significant ? ", significant" : "");
    return r;
  };
  const Result free_wrong = run(-1, 0.3);
  EXPECT_EQ(free_wrong.loops, 1);
  EXPECT_TRUE(free_wrong.significant) << "the case the rule is for: the loop would correct";
  EXPECT_EQ(run(4, 0.3).loops, 0) << "held keyframe 4 shared a window with the candidate";
  const Result held_far = run(33, 0.3);
  EXPECT_EQ(held_far.loops, 1) << "30 steps of chain between the held keyframe and the candidate";
  EXPECT_TRUE(held_far.significant);
}

// A camera going round the circle three times: the first lap's keyframes are kept (the map), the
// later laps' are culled (redundant with it), each tied by the window to the first-lap keyframe
// at its place. The culled keyframes leave the pose graph once pose_graph_recent_keyframes newer
// ones were processed: the graph stays the size of the map plus the recent ones, and every fold
// is reported with the vertex the keyframe follows from then on.
TEST(LoopCloser, CulledKeyframesLeaveThePoseGraphOnceOld) {
  const int n = 24, laps = 3, recent = 6;
  LoopConfig c = config();
  c.pose_graph_recent_keyframes = recent;
  LoopCloser closer(c, test::testCamera(500.0), /*inline_mode=*/true);
  std::map<int, int> follows;
  std::size_t most_vertices = 0;
  for (int k = 0; k < laps * n; ++k) {
    LoopJob job = keyframe(k, truePose(k, n));
    if (k + 1 < laps * n)
      job.links.push_back(link(k + 1, truePose(k, n), truePose(k + 1, n), false));
    if (k >= n) {
      job.culled = true;
      job.links.push_back(link(k % n, truePose(k, n), truePose(k % n, n), true));
    }
    closer.keyframeLeftWindow(std::move(job));
    for (const LoopCorrection& corr : closer.takeCorrections())
      for (const auto& [id, anchor] : corr.folded) follows[id] = anchor;
    most_vertices = std::max(most_vertices, static_cast<std::size_t>(closer.graphVertices()));
  }
  closer.flush();
  for (const LoopCorrection& corr : closer.takeCorrections())
    for (const auto& [id, anchor] : corr.folded) follows[id] = anchor;
  // The map's n keyframes and the culled ones processed fewer than `recent` keyframes ago.
  EXPECT_LE(most_vertices, static_cast<std::size_t>(n + recent));
  EXPECT_EQ(closer.graphVertices(), n + recent - 1);
  // Parallel edges are fused: a few per kept keyframe, not one per keyframe ever made.
  EXPECT_LE(closer.graphEdges(), 4 * n);
  // Every culled keyframe but the recent ones was folded; it follows a vertex or another folded
  // keyframe, and the chain ends at a keyframe of the map.
  const int folded = laps * n - n - (recent - 1);
  EXPECT_EQ(static_cast<int>(follows.size()), folded);
  for (const auto& [id, anchor] : follows) {
    EXPECT_GE(id, n);
    int root = anchor;
    for (int guard = 0; follows.count(root) != 0 && guard < laps * n; ++guard) root = follows[root];
    EXPECT_TRUE(root < n || root >= laps * n - (recent - 1)) << id << " follows " << anchor;
  }
}

// The end of a threaded run: flush() processes the queue and the pending pose graph within
// loop.finish_timeout_s; what outlasts it is abandoned (the task is stopped, so the graph can be
// read at once) and counted, never left running behind the caller. A stopped loop closer refuses
// the keyframes that come after.
struct ThreadedEnd {
  std::int64_t vertices = 0;
  std::uint64_t unfinished = 0, dropped_before = 0, dropped_after = 0, unfinished_again = 0;
};

ThreadedEnd runThreaded(double finish_timeout_s) {
  const int n = 16;
  LoopConfig c = config();
  c.finish_timeout_s = finish_timeout_s;
  LoopCloser closer(c, test::testCamera(500.0), /*inline_mode=*/false);
  test::SceneRandom rnd(7);
  // Made first and handed over in one burst, so that the worker has 16 keyframes of 300 corners
  // to index and query (about 1 ms each here) when flush() is called.
  std::vector<LoopJob> jobs;
  for (int k = 0; k < n; ++k) {
    jobs.push_back(keyframe(k, truePose(k, 2 * n)));
    describe(jobs.back(), nullptr, rnd);
    if (k + 1 < n)
      jobs.back().links.push_back(link(k + 1, truePose(k, 2 * n), truePose(k + 1, 2 * n), false));
  }
  for (LoopJob& job : jobs) closer.keyframeLeftWindow(std::move(job));
  ThreadedEnd r;
  r.dropped_before = closer.droppedKeyframes();  // the queue holds all 16
  closer.flush();
  r.unfinished = closer.unfinishedJobs();
  // The task is idle or stopped: exporting the graph does not race with it.
  std::vector<int> ids(n);
  for (int k = 0; k < n; ++k) ids[static_cast<std::size_t>(k)] = k;
  const LoopCloser::GraphExport g = closer.exportGraph(ids, {});
  EXPECT_LE(g.edges.size(), static_cast<std::size_t>(2 * n));
  r.vertices = closer.graphVertices();
  // One more keyframe and another end of run (a map saved again later in the session).
  LoopJob late = keyframe(n, truePose(n, 2 * n));
  closer.keyframeLeftWindow(std::move(late));
  closer.flush();
  r.dropped_after = closer.droppedKeyframes();
  r.unfinished_again = closer.unfinishedJobs();
  return r;
}

TEST(LoopCloser, FlushProcessesEverythingWithinItsTime) {
  const ThreadedEnd r = runThreaded(60.0);
  EXPECT_EQ(r.dropped_before, 0u);
  EXPECT_EQ(r.vertices, 16);
  EXPECT_EQ(r.unfinished, 0u);
  EXPECT_EQ(r.dropped_after, 0u);  // it keeps running: the late keyframe was processed
  EXPECT_EQ(r.unfinished_again, 0u);
}

TEST(LoopCloser, FlushAbandonsWhatOutlastsItsTimeAndCountsIt) {
  const ThreadedEnd r = runThreaded(0.0);
  EXPECT_EQ(r.dropped_before, 0u);
  // No time at all: the worker cannot have indexed and queried the 16 keyframes handed over
  // microseconds before (and with 0 s even the final pose-graph run is abandoned).
  EXPECT_GT(r.unfinished, 0u);
  EXPECT_LE(r.unfinished, 16u);
  // Every keyframe processed is a vertex; the one the abort cut short (counted unfinished) may
  // be one too.
  EXPECT_GE(r.vertices, 16 - static_cast<std::int64_t>(r.unfinished));
  EXPECT_LE(r.vertices, 16 - static_cast<std::int64_t>(r.unfinished) + 1);
  // Stopped for the session: the late keyframe is refused and counted; a second end of run
  // reports the same unfinished jobs and no new warning.
  EXPECT_EQ(r.dropped_after, 1u);
  EXPECT_EQ(r.unfinished_again, r.unfinished);
}

}  // namespace
}  // namespace ldsm::loop
