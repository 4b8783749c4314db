// Sim(3) pose graph: a drifting loop closed by one loop edge comes back near the ground truth; a
// consistent graph without loop stays put; weights and information act as documented; the abort
// flag stops a solve and leaves the vertices unchanged; bad input throws.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <map>
#include <random>
#include <thread>

#include "ldsm/error.h"
#include "loop/pose_graph.h"

namespace ldsm::loop {
namespace {

using Tangent = Sim3d::Tangent;

// Ground truth: N keyframes on a circle of radius 10 (camera looking along the tangent, varying
// height), scale 1.
std::vector<Sim3d> circle(int n) {
  std::vector<Sim3d> g;
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * M_PI * i / n;
    const SO3d R = SO3d::exp(Eigen::Vector3d(0, -a, 0));
    g.emplace_back(R, Eigen::Vector3d(10 * std::sin(a), 0.5 * std::sin(3 * a), 10 * std::cos(a)),
                   1.0);
  }
  return g;
}

// Odometry with a systematic drift per step (yaw, roll, scale) plus noise, chained from vertex 0.
struct DriftingGraph {
  std::vector<Sim3d> truth, estimate;
  PoseGraph graph;
};

DriftingGraph makeDriftingLoop(int n, bool with_loop, unsigned seed, double drift = 1.0) {
  DriftingGraph d;
  d.truth = circle(n);
  std::mt19937 rng(seed);
  std::normal_distribution<double> N(0.0, 1.0);
  Tangent bias;
  bias << 0.0, 0.0, 0.0, 0.004, 0.006, 0.0, 0.012;  // 0.23 deg roll, 0.34 deg yaw, 1.2 % scale
  bias *= drift;
  d.estimate.push_back(d.truth[0]);
  std::vector<Sim3d> meas;
  for (int i = 0; i + 1 < n; ++i) {
    Tangent noise;
    for (int k = 0; k < 7; ++k) noise(k) = 0.002 * N(rng);
    const Sim3d rel = d.truth[i].inverse() * d.truth[i + 1];
    meas.push_back(rel * Sim3d::exp(bias + noise));
    d.estimate.push_back(d.estimate.back() * meas.back());
  }
  for (int i = 0; i < n; ++i) d.graph.addVertex(i, d.estimate[i]);
  for (int i = 0; i + 1 < n; ++i) {
    d.graph.addEdge(i, i + 1, meas[i], kDefaultOdometryEdgeWeight, PoseGraphEdgeKind::kOdometry);
  }
  if (with_loop) {
    // The current keyframe (n - 1) sees keyframe 0 again: exact relative Sim(3).
    d.graph.addEdge(n - 1, 0, d.truth[n - 1].inverse() * d.truth[0], kDefaultLoopEdgeWeight,
                    PoseGraphEdgeKind::kLoop);
  }
  d.graph.setFixed(n - 1);
  return d;
}

// RMS position error after mapping the estimate's world onto the truth through the fixed
// (current) vertex, which is how the corrected map is used.
double anchoredRmse(const std::vector<Sim3d>& truth, const std::vector<Sim3d>& est) {
  const Sim3d A = truth.back() * est.back().inverse();
  double s = 0.0;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    s += ((A * est[i]).translation() - truth[i].translation()).squaredNorm();
  }
  return std::sqrt(s / static_cast<double>(truth.size()));
}

std::vector<Sim3d> estimates(const PoseGraph& g, int n) {
  std::vector<Sim3d> e;
  for (int i = 0; i < n; ++i) e.push_back(g.vertex(i));
  return e;
}

// Equal up to the rounding of storing a vertex (quaternion, translation, log scale).
void expectSame(const Sim3d& a, const Sim3d& b) {
  EXPECT_LT((a.matrix() - b.matrix()).norm(), 1e-12 * (1.0 + b.matrix().norm()));
}

TEST(PoseGraph, LoopEdgeCorrectsAccumulatedDrift) {
  constexpr int n = 60;
  DriftingGraph d = makeDriftingLoop(n, true, 1);
  const double before = anchoredRmse(d.truth, d.estimate);
  const Sim3d fixed_before = d.graph.vertex(n - 1);
  const PoseGraphSolveSummary s = d.graph.optimize({});
  ASSERT_TRUE(s.updated) << s.message;
  EXPECT_FALSE(s.aborted);
  EXPECT_TRUE(s.converged) << s.message;
  EXPECT_LT(s.final_cost, s.initial_cost);
  const std::vector<Sim3d> after_est = estimates(d.graph, n);
  const double after = anchoredRmse(d.truth, after_est);
  // ~4 m of error over a 63 m loop before. The same bias in every odometry edge also bends the
  // shape, which one loop edge cannot undo entirely: a few decimetres remain.
  EXPECT_GT(before, 2.0);
  EXPECT_LT(after, 0.1 * before) << "before " << before << " after " << after;
  EXPECT_LT(after, 0.4);
  // The current keyframe is fixed.
  EXPECT_LT((d.graph.vertex(n - 1).matrix() - fixed_before.matrix()).norm(), 1e-12);
  // The loop's scale drift is spread back: relative scales return to 1 within a few percent.
  const Sim3d A = d.truth.back() * after_est.back().inverse();
  for (int i = 0; i < n; ++i) EXPECT_NEAR((A * after_est[i]).scale(), 1.0, 0.03) << i;
  // The solver's cost is the documented 0.5 r^T Info r.
  EXPECT_NEAR(s.final_cost, d.graph.cost(), 1e-9 * std::max(1.0, s.final_cost));
}

TEST(PoseGraph, ConsistentGraphWithoutLoopStaysPut) {
  constexpr int n = 30;
  DriftingGraph d = makeDriftingLoop(n, false, 2);
  // Extra covisibility edges consistent with the current estimates (as taken from the window).
  for (int i = 0; i + 3 < n; ++i) {
    d.graph.addEdge(i, i + 3, d.estimate[i].inverse() * d.estimate[i + 3], 0.5,
                    PoseGraphEdgeKind::kOdometry);
  }
  EXPECT_LT(d.graph.cost(), 1e-20);
  const PoseGraphSolveSummary s = d.graph.optimize({});
  EXPECT_TRUE(s.updated) << s.message;
  for (int i = 0; i < n; ++i) {
    EXPECT_LT((d.graph.vertex(i).matrix() - d.estimate[i].matrix()).norm(), 1e-9) << i;
  }
}

TEST(PoseGraph, InformationWeightsTheMeasurements) {
  // Two contradicting measurements of the same relative pose, weights 1 and 100: the solution
  // lies at the weighted mean (in the tangent space, to first order).
  PoseGraph g;
  g.addVertex(0, Sim3d());
  g.addVertex(1, Sim3d());
  g.setFixed(0);
  const Tangent a = (Tangent() << 1.0, 0, 0, 0, 0.1, 0, 0.0).finished();
  const Tangent b = (Tangent() << 1.2, 0, 0, 0, 0.1, 0, 0.05).finished();
  g.addEdge(0, 1, Sim3d::exp(a), 1.0, PoseGraphEdgeKind::kOdometry);
  g.addEdge(0, 1, Sim3d::exp(b), 100.0, PoseGraphEdgeKind::kLoop);
  ASSERT_TRUE(g.optimize({}).updated);
  const Tangent x = g.vertex(1).log();
  const Tangent expected = (a + 100.0 * b) / 101.0;
  EXPECT_LT((x - expected).norm(), 2e-3) << x.transpose();
  EXPECT_LT((x - b).norm(), 0.03 * (a - b).norm());
  // A full information matrix: only the rotation of the heavy edge is trusted.
  PoseGraph h;
  h.addVertex(0, Sim3d());
  h.addVertex(1, Sim3d());
  h.setFixed(0);
  Matrix7d info = Matrix7d::Identity();
  info.block<3, 3>(0, 0) *= 1e-6;
  info(6, 6) = 1e-6;
  info.block<3, 3>(3, 3) *= 1e4;
  const Tangent c = (Tangent() << 3.0, 0, 0, 0, 0, 0.2, 0.5).finished();
  h.addEdge(0, 1, Sim3d::exp(a), 1.0, PoseGraphEdgeKind::kOdometry);
  h.addEdge(PoseGraphEdge{0, 1, Sim3d::exp(c), info, PoseGraphEdgeKind::kLoop});
  ASSERT_TRUE(h.optimize({}).updated);
  const Sim3d v = h.vertex(1);
  EXPECT_LT((v.so3().log() - SO3d::exp(c.segment<3>(3)).log()).norm(), 1e-3);
  EXPECT_NEAR(v.scale(), 1.0, 1e-3);  // the scale of `a`
}

TEST(PoseGraph, PresetAbortFlagLeavesVerticesUnchanged) {
  DriftingGraph d = makeDriftingLoop(40, true, 3);
  const std::atomic<bool> abort{true};
  PoseGraphSolveOptions o;
  o.abort = &abort;
  const PoseGraphSolveSummary s = d.graph.optimize(o);
  EXPECT_TRUE(s.aborted);
  EXPECT_FALSE(s.updated);
  for (int i = 0; i < 40; ++i) expectSame(d.graph.vertex(i), d.estimate[i]);
}

TEST(PoseGraph, AbortDuringSolveStopsPromptly) {
  // A large graph with many loop edges: the solve takes far longer than the 20 ms after which the
  // flag is raised.
  constexpr int n = 3000;
  DriftingGraph d = makeDriftingLoop(n, true, 4, 0.02);
  for (int i = 0; i + 500 < n; i += 7) {
    d.graph.addEdge(i, i + 500, d.truth[i].inverse() * d.truth[i + 500], 10.0,
                    PoseGraphEdgeKind::kLoop);
  }
  std::atomic<bool> abort{false};
  PoseGraphSolveOptions o;
  o.abort = &abort;
  o.max_iterations = 500;
  o.max_time_s = 60.0;
  o.function_tolerance = 1e-300;
  std::thread raiser([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    abort.store(true);
  });
  const PoseGraphSolveSummary s = d.graph.optimize(o);
  raiser.join();
  EXPECT_TRUE(s.aborted) << s.message << " after " << s.iterations << " iterations";
  EXPECT_FALSE(s.updated);
  EXPECT_LT(s.time_s, 10.0);
  for (int i = 0; i < n; i += 97) expectSame(d.graph.vertex(i), d.estimate[i]);
}

TEST(PoseGraph, GaugeIsFixedWhenNoVertexIs) {
  DriftingGraph d = makeDriftingLoop(20, true, 5);
  d.graph.setFixed(19, false);
  const Sim3d first = d.graph.vertex(0);
  ASSERT_TRUE(d.graph.optimize({}).updated);
  EXPECT_LT((d.graph.vertex(0).matrix() - first.matrix()).norm(), 1e-12);  // lowest id fixed
  EXPECT_FALSE(d.graph.isFixed(0));
}

TEST(PoseGraph, FixedVerticesStayWhereTheyAre) {
  DriftingGraph d = makeDriftingLoop(20, true, 6);
  for (int i = 12; i < 20; ++i) d.graph.setFixed(i);  // e.g. the whole active window
  ASSERT_TRUE(d.graph.optimize({}).updated);
  const std::map<int, Sim3d> v = d.graph.vertices();
  ASSERT_EQ(v.size(), 20u);
  for (int i = 12; i < 20; ++i) expectSame(v.at(i), d.estimate[i]);
  EXPECT_GT((v.at(3).matrix() - d.estimate[3].matrix()).norm(), 1e-3);  // the rest moved
  // Everything fixed: nothing to optimise, nothing changes, no error.
  for (int i = 0; i < 20; ++i) d.graph.setFixed(i);
  const PoseGraphSolveSummary s = d.graph.optimize({});
  EXPECT_FALSE(s.aborted);
  for (int i = 0; i < 20; ++i) expectSame(d.graph.vertex(i), v.at(i));
}

TEST(PoseGraph, BadInputThrows) {
  PoseGraph g;
  g.addVertex(1, Sim3d());
  g.addVertex(2, Sim3d());
  EXPECT_THROW(g.addVertex(1, Sim3d()), InputError);
  Sim3d nan_pose;
  nan_pose.translation().x() = std::nan("");
  EXPECT_THROW(g.addVertex(3, nan_pose), InputError);
  EXPECT_THROW(g.setVertex(2, nan_pose), InputError);
  EXPECT_THROW(g.vertex(7), InputError);
  EXPECT_THROW(g.setFixed(7), InputError);
  EXPECT_THROW(g.addEdge(1, 7, Sim3d(), 1.0, PoseGraphEdgeKind::kOdometry), InputError);
  EXPECT_THROW(g.addEdge(1, 1, Sim3d(), 1.0, PoseGraphEdgeKind::kOdometry), InputError);
  EXPECT_THROW(g.addEdge(1, 2, Sim3d(), 0.0, PoseGraphEdgeKind::kOdometry), InputError);
  EXPECT_THROW(g.addEdge(1, 2, nan_pose, 1.0, PoseGraphEdgeKind::kOdometry), InputError);
  Matrix7d info = Matrix7d::Identity();
  info(0, 0) = -1;
  EXPECT_THROW(g.addEdge(PoseGraphEdge{1, 2, Sim3d(), info, PoseGraphEdgeKind::kLoop}), InputError);
  info = Matrix7d::Identity();
  info(0, 1) = 0.5;  // not symmetric
  EXPECT_THROW(g.addEdge(PoseGraphEdge{1, 2, Sim3d(), info, PoseGraphEdgeKind::kLoop}), InputError);
  EXPECT_TRUE(g.edges().empty());
  PoseGraphSolveOptions o;
  o.max_iterations = 0;
  EXPECT_THROW(g.optimize(o), ConfigError);
  EXPECT_FALSE(g.optimize({}).updated);  // no edges: nothing to do
}

}  // namespace
}  // namespace ldsm::loop
