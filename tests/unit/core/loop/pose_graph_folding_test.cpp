// Folding a vertex out of the pose graph: the rerouted edge's measurement and covariance agree
// with numeric differentiation of the composed residual (both edge directions and a link stored
// either way); folding chain vertices keeps the optimum of the rest (the chain's Gaussian
// marginalisation, to first order); parallel edges are fused; bad calls throw.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>

#include <Eigen/Cholesky>

#include "ldsm/error.h"
#include "loop/pose_graph.h"

namespace ldsm::loop {
namespace {

using Tangent = Sim3d::Tangent;

Sim3d randomSim3(std::mt19937& rng, double size) {
  std::normal_distribution<double> N(0.0, 1.0);
  Tangent x;
  for (int k = 0; k < 7; ++k) x(k) = size * N(rng);
  x(6) *= 0.3;
  return Sim3d::exp(x);
}

Matrix7d randomCovariance(std::mt19937& rng, double size) {
  std::normal_distribution<double> N(0.0, 1.0);
  Matrix7d A;
  for (int i = 0; i < 7; ++i)
    for (int j = 0; j < 7; ++j) A(i, j) = N(rng);
  return size * size * (A * A.transpose() + 0.5 * Matrix7d::Identity());
}

Matrix7d inverse(const Matrix7d& A) {
  return A.ldlt().solve(Matrix7d::Identity());
}

// Jacobian of f at 0 by central differences.
template <typename F>
Matrix7d numericJacobian(const F& f) {
  constexpr double h = 1e-6;
  Matrix7d J;
  for (int k = 0; k < 7; ++k) {
    Tangent d = Tangent::Zero();
    d(k) = h;
    J.col(k) = (f(d) - f(-d)) / (2.0 * h);
  }
  return J;
}

void expectNear(const Matrix7d& a, const Matrix7d& b, double rel) {
  EXPECT_LT((a - b).norm(), rel * b.norm()) << "got\n" << a << "\nexpected\n" << b;
}

struct FoldCase {
  bool link_from_anchor;  // the link stored p -> v (else v -> p)
  bool edge_from_folded;  // the other edge stored v -> x (else x -> v)
};

class FoldedEdge : public ::testing::TestWithParam<FoldCase> {};

TEST_P(FoldedEdge, MeasurementAndCovarianceMatchNumericDifferentiation) {
  const FoldCase c = GetParam();
  std::mt19937 rng(7 + 2 * c.link_from_anchor + c.edge_from_folded);
  const Sim3d S_link = randomSim3(rng, 0.4), S_edge = randomSim3(rng, 0.6);
  const Matrix7d cov_link = randomCovariance(rng, 0.01), cov_edge = randomCovariance(rng, 0.02);
  constexpr int p = 0, v = 1, x = 2;
  PoseGraph g;
  for (int id : {p, v, x}) g.addVertex(id, Sim3d());
  g.addEdge(PoseGraphEdge{c.link_from_anchor ? p : v, c.link_from_anchor ? v : p, S_link,
                          inverse(cov_link), PoseGraphEdgeKind::kOdometry});
  g.addEdge(PoseGraphEdge{c.edge_from_folded ? v : x, c.edge_from_folded ? x : v, S_edge,
                          inverse(cov_edge), PoseGraphEdgeKind::kReuse});
  EXPECT_EQ(g.foldVertex(v, p), 1);
  ASSERT_EQ(g.edges().size(), 1u);
  EXPECT_FALSE(g.hasVertex(v));
  const PoseGraphEdge& e = g.edges()[0];
  EXPECT_EQ(e.kind, PoseGraphEdgeKind::kReuse);
  EXPECT_EQ(e.from_id, c.edge_from_folded ? p : x);
  EXPECT_EQ(e.to_id, c.edge_from_folded ? x : p);

  // The true poses as functions of the two edges' noises (S_j = S_i M exp(r) for each stored
  // edge i -> j), and the folded edge's residual at them.
  const Sim3d S_w_p = randomSim3(rng, 1.0);
  const auto residual = [&](const Tangent& r_link, const Tangent& r_edge) {
    const Sim3d S_w_v = c.link_from_anchor ? S_w_p * S_link * Sim3d::exp(r_link)
                                           : S_w_p * Sim3d::exp(-r_link) * S_link.inverse();
    const Sim3d S_w_x = c.edge_from_folded ? S_w_v * S_edge * Sim3d::exp(r_edge)
                                           : S_w_v * Sim3d::exp(-r_edge) * S_edge.inverse();
    const Sim3d S_w_from = e.from_id == p ? S_w_p : S_w_x;
    const Sim3d S_w_to = e.to_id == p ? S_w_p : S_w_x;
    return sim3EdgeResidual(e.S_from_to, S_w_from, S_w_to);
  };
  // Noise-free poses satisfy the folded measurement exactly.
  EXPECT_LT(residual(Tangent::Zero(), Tangent::Zero()).norm(), 1e-12);
  const Matrix7d J_link =
      numericJacobian([&](const Tangent& d) { return residual(d, Tangent::Zero()); });
  const Matrix7d J_edge =
      numericJacobian([&](const Tangent& d) { return residual(Tangent::Zero(), d); });
  const Matrix7d expected =
      J_link * cov_link * J_link.transpose() + J_edge * cov_edge * J_edge.transpose();
  expectNear(inverse(e.information), expected, 1e-6);
}

INSTANTIATE_TEST_SUITE_P(LinkAndEdgeDirections, FoldedEdge,
                         ::testing::Values(FoldCase{true, true}, FoldCase{true, false},
                                           FoldCase{false, true}, FoldCase{false, false}));

// A loop of n keyframes with biased odometry and one loop edge (as in pose_graph_test.cpp).
PoseGraph driftingLoop(int n, std::vector<Sim3d>* truth) {
  std::mt19937 rng(3);
  std::normal_distribution<double> N(0.0, 1.0);
  truth->clear();
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * M_PI * i / n;
    truth->emplace_back(SO3d::exp(Eigen::Vector3d(0, -a, 0)),
                        Eigen::Vector3d(10 * std::sin(a), 0.5 * std::sin(3 * a), 10 * std::cos(a)),
                        1.0);
  }
  Tangent bias;
  bias << 0.0, 0.0, 0.0, 0.004, 0.006, 0.0, 0.012;
  PoseGraph g;
  Sim3d S = (*truth)[0];
  g.addVertex(0, S);
  const Matrix7d odometry_info =
      (Tangent() << 1e4, 1e4, 1e4, 4e6, 4e6, 4e6, 2.5e5).finished().asDiagonal();
  for (int i = 0; i + 1 < n; ++i) {
    Tangent noise;
    for (int k = 0; k < 7; ++k) noise(k) = 0.002 * N(rng);
    const Sim3d M = (*truth)[i].inverse() * (*truth)[i + 1] * Sim3d::exp(bias + noise);
    S = S * M;
    g.addVertex(i + 1, S);
    g.addEdge(PoseGraphEdge{i, i + 1, M, odometry_info, PoseGraphEdgeKind::kOdometry});
  }
  g.addEdge(PoseGraphEdge{n - 1, 0, (*truth)[n - 1].inverse() * (*truth)[0], 100.0 * odometry_info,
                          PoseGraphEdgeKind::kLoop});
  g.setFixed(n - 1);
  return g;
}

TEST(PoseGraphFolding, FoldingChainVerticesKeepsTheOptimumOfTheRest) {
  constexpr int n = 24;
  std::vector<Sim3d> truth;
  PoseGraph full = driftingLoop(n, &truth);
  PoseGraph folded = full;
  const std::vector<int> gone = {3, 4, 9, 15, 16, 17, 22};
  for (std::size_t k = 0; k < gone.size(); ++k) {
    int anchor = gone[k] - 1;  // the nearest earlier vertex still in the graph
    while (std::find(gone.begin(), gone.begin() + static_cast<std::ptrdiff_t>(k), anchor) !=
           gone.begin() + static_cast<std::ptrdiff_t>(k))
      --anchor;
    EXPECT_EQ(folded.foldVertex(gone[k], anchor), 1) << gone[k];
  }
  EXPECT_EQ(folded.numVertices(), static_cast<std::size_t>(n) - gone.size());
  EXPECT_EQ(folded.edges().size(), full.edges().size() - gone.size());
  const std::map<int, Sim3d> before = full.vertices();
  ASSERT_TRUE(full.optimize({}).updated);
  ASSERT_TRUE(folded.optimize({}).updated);
  double worst = 0.0, largest_move = 0.0;
  for (const auto& [id, S] : folded.vertices()) {
    worst = std::max(worst, (S.translation() - full.vertex(id).translation()).norm());
    largest_move = std::max(largest_move,
                            (full.vertex(id).translation() - before.at(id).translation()).norm());
  }
  // The loop moves keyframes by metres; folding changes the solution by a small fraction of
  // that (first-order marginalisation; the rest is the linearisation of the composed edges).
  std::printf("folded chain: solutions %.5f apart, keyframes moved up to %.3f\n", worst,
              largest_move);
  EXPECT_GT(largest_move, 1.0);
  EXPECT_LT(worst, 0.01 * largest_move) << "worst " << worst << " of " << largest_move;
}

TEST(PoseGraphFolding, ParallelEdgesAreFusedAndKeepTheOptimum) {
  // A kept keyframe K (0) followed by two culled ones (1, 2), each measuring a map keyframe M (3).
  std::mt19937 rng(11);
  PoseGraph g;
  const Sim3d S0 = randomSim3(rng, 0.5), S1 = S0 * randomSim3(rng, 0.2),
              S2 = S1 * randomSim3(rng, 0.2), S3 = S0 * randomSim3(rng, 0.5);
  g.addVertex(0, S0);
  g.addVertex(1, S1);
  g.addVertex(2, S2);
  g.addVertex(3, S3 * randomSim3(rng, 0.05));  // M's estimate is off
  const Matrix7d odo = inverse(randomCovariance(rng, 0.01));
  g.addEdge(PoseGraphEdge{0, 1, S0.inverse() * S1, odo, PoseGraphEdgeKind::kOdometry});
  g.addEdge(PoseGraphEdge{1, 2, S1.inverse() * S2, odo, PoseGraphEdgeKind::kOdometry});
  // Two slightly different measurements of M, one stored each way.
  g.addEdge(PoseGraphEdge{1, 3, S1.inverse() * S3 * randomSim3(rng, 0.01),
                          inverse(randomCovariance(rng, 0.02)), PoseGraphEdgeKind::kReuse});
  g.addEdge(PoseGraphEdge{3, 2, (S2.inverse() * S3 * randomSim3(rng, 0.01)).inverse(),
                          inverse(randomCovariance(rng, 0.02)), PoseGraphEdgeKind::kReuse});
  g.setFixed(0);
  PoseGraph folded = g;
  folded.foldVertex(1, 0);
  folded.foldVertex(2, 0);
  // One edge 0 - 3 remains: the two measurements fused.
  ASSERT_EQ(folded.edges().size(), 1u);
  const Sim3d M_start = g.vertex(3);
  ASSERT_TRUE(g.optimize({}).updated);
  ASSERT_TRUE(folded.optimize({}).updated);
  // The rerouted edges share the link's noise, whose correlation folding drops: close to the
  // optimum, not exactly at it; the estimate started 5 % off.
  const double start = (M_start.translation() - g.vertex(3).translation()).norm();
  const double err = (folded.vertex(3).translation() - g.vertex(3).translation()).norm();
  std::printf("fused: start %.5f, folded vs full %.5f\n", start, err);
  EXPECT_LT(err, 0.2 * start);
}

TEST(PoseGraphFolding, BadCallsThrowAndLeaveTheGraph) {
  PoseGraph g;
  for (int id = 0; id < 3; ++id) g.addVertex(id, Sim3d());
  g.addEdge(0, 1, Sim3d(), 1.0, PoseGraphEdgeKind::kOdometry);
  EXPECT_THROW(g.foldVertex(1, 1), InputError);
  EXPECT_THROW(g.foldVertex(1, 2), InputError);  // no edge between them
  EXPECT_THROW(g.foldVertex(5, 0), InputError);
  EXPECT_THROW(g.removeIsolatedVertex(1), InputError);
  EXPECT_EQ(g.numVertices(), 3u);
  EXPECT_EQ(g.edges().size(), 1u);
  g.removeIsolatedVertex(2);
  EXPECT_FALSE(g.hasVertex(2));
  EXPECT_EQ(g.foldVertex(1, 0), 0);  // only the link: nothing to reroute
  EXPECT_TRUE(g.edges().empty());
}

}  // namespace
}  // namespace ldsm::loop
