// Sim(3) pose graph of the keyframes (LDSO section III-D, LDSM's weighting): one vertex per
// keyframe holding its world-from-camera similarity S_w_c, one edge per relative measurement
//   S_i_j ~ S_w_i^-1 * S_w_j   (maps camera-j points into camera i)
// with residual r = log(S_i_j^-1 * S_w_i^-1 * S_w_j) in R^7 ([rho, phi, sigma]) and cost
// r^T Info r. Each edge carries its own information matrix: the loop closer gives odometry edges
// that of its drift model (odometry_drift.h) and loop edges the loop's measured information
// (LDSM's fixed weights, loop 100 and odometry 1, remain as constants for scalar use). Solved with
// Ceres: Levenberg-Marquardt, SPARSE_NORMAL_CHOLESKY on SuiteSparse, analytic Jacobians
// (sim3_edge.h, checked against numeric differentiation in the tests; ~10x cheaper than autodiff
// through Sim3::log), bounded iterations and time, abortable. Not thread-safe: one thread builds
// and solves a graph (the loop-closing worker).
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "loop/sim3_edge.h"
#include "math/sim3.h"

namespace ldsm::loop {

/// What an edge comes from (affects nothing but bookkeeping; weights are explicit).
enum class PoseGraphEdgeKind {
  kOdometry,  ///< consecutive keyframes, from the window
  kLoop,      ///< a verified loop
  kReuse,     ///< a keyframe and a map keyframe brought back into its window (map reuse)
};

/// LDSM's fixed weights: loop edges 100, window edges 1 (for addEdge with a scalar weight).
inline constexpr double kDefaultOdometryEdgeWeight = 1.0;
inline constexpr double kDefaultLoopEdgeWeight = 100.0;

/// A relative Sim(3) measurement between two keyframes.
struct PoseGraphEdge {
  int from_id = -1;                             ///< i
  int to_id = -1;                               ///< j
  Sim3d S_from_to;                              ///< S_i_j: maps points of camera j into camera i
  Matrix7d information = Matrix7d::Identity();  ///< symmetric positive definite, tangent order
  PoseGraphEdgeKind kind = PoseGraphEdgeKind::kOdometry;
};

/// log det of an information matrix (symmetric positive definite): how certain an edge is, for
/// comparing edges.
double informationLogDet(const Matrix7d& information);

/// Solver limits of PoseGraph::optimize().
struct PoseGraphSolveOptions {
  int max_iterations = 50;
  double max_time_s = 2.0;
  double function_tolerance = 1e-10;  ///< relative cost decrease to stop at
  /// Checked after every iteration; when it becomes true the solve stops and the vertices keep
  /// the values they had before optimize() (nullptr: never aborts).
  const std::atomic<bool>* abort = nullptr;
  /// Multiplies the information of every odometry edge (an a-posteriori scale of the odometry's
  /// drift model: < 1 when a loop shows more drift than the model expected).
  double odometry_information_scale = 1.0;
};

/// What PoseGraph::optimize() did.
struct PoseGraphSolveSummary {
  bool updated = false;    ///< vertices were overwritten with the solution
  bool aborted = false;    ///< stopped by the abort flag (vertices unchanged)
  bool converged = false;  ///< a convergence tolerance was reached
  int iterations = 0;
  double initial_cost = 0.0;  ///< 0.5 sum r^T Info r
  double final_cost = 0.0;
  double time_s = 0.0;
  std::string message;  ///< the solver's report
};

class PoseGraph {
 public:
  /// Adds a keyframe vertex. Throws InputError if the id exists or the pose is not finite.
  void addVertex(int id, const Sim3d& S_world_camera);
  /// Overwrites a vertex estimate. Throws InputError for an unknown id or a non-finite pose.
  void setVertex(int id, const Sim3d& S_world_camera);
  bool hasVertex(int id) const { return vertices_.count(id) != 0; }
  /// The current estimate of a vertex. Throws InputError for an unknown id.
  Sim3d vertex(int id) const;
  /// All vertex estimates by keyframe id.
  std::map<int, Sim3d> vertices() const;
  /// Holds a vertex constant (the current keyframe; optionally the active window). When no vertex
  /// of the optimised graph is fixed, optimize() fixes the one with the lowest id (gauge).
  void setFixed(int id, bool fixed = true);
  bool isFixed(int id) const;

  /// Adds an edge; both vertices must exist. Throws InputError for unknown ids, from == to, a
  /// non-finite measurement or an information matrix that is not symmetric positive definite.
  void addEdge(const PoseGraphEdge& edge);
  /// Convenience: edge with information weight * I.
  void addEdge(int from_id, int to_id, const Sim3d& S_from_to, double weight,
               PoseGraphEdgeKind kind);
  const std::vector<PoseGraphEdge>& edges() const { return edges_; }
  std::size_t numVertices() const { return vertices_.size(); }

  /// Takes vertex `id` out of the graph (pose_graph_folding.cpp): each of its edges to a third
  /// vertex x is re-expressed at `anchor` through the edge that links the two (the most certain
  /// one, informationLogDet, when there are several), composing the measurements and, to first
  /// order, adding the link's uncertainty to the rerouted edge's; a rerouted edge that joins an
  /// existing edge of the same kind between the same two vertices is fused with it
  /// (information-weighted). Edges between `id` and `anchor` go with the vertex. Bounds the graph
  /// by the keyframes that are kept: a keyframe no longer needed as a vertex leaves its
  /// measurements to a neighbour. Throws InputError for an unknown vertex, anchor == id, or an
  /// anchor without an edge to id while id has other edges. Returns the number of edges rerouted.
  int foldVertex(int id, int anchor);
  /// Removes a vertex with no edges. Throws InputError when it is unknown or has edges.
  void removeIsolatedVertex(int id);

  /// The residual of an edge at the current estimates, log(S_i_j^-1 S_w_i^-1 S_w_j).
  Vector7d edgeResidual(const PoseGraphEdge& edge) const;
  /// 0.5 sum over edges of r^T Info r at the current estimates.
  double cost() const;

  /// Optimises all non-fixed vertices that have edges. Throws ConfigError for bad options.
  PoseGraphSolveSummary optimize(const PoseGraphSolveOptions& options);

 private:
  struct Vertex {
    std::array<double, 8> params{};  ///< quaternion x, y, z, w; translation; log scale
    bool fixed = false;
  };
  const Vertex& at(int id) const;
  /// Adds an edge whose information was already checked, or fuses it into an existing edge of
  /// the same kind between the same two vertices (either direction).
  void addOrFuseEdge(PoseGraphEdge edge);

  std::map<int, Vertex> vertices_;  // node-based: parameter addresses stay valid while solving
  std::vector<PoseGraphEdge> edges_;
  std::vector<Matrix7d> sqrt_information_;  // L^T with Info = L L^T, per edge
};

}  // namespace ldsm::loop
