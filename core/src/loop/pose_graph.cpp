#include "loop/pose_graph.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <string>

#include <ceres/ceres.h>
#include <Eigen/Cholesky>

#include "ldsm/error.h"
#include "math/constants.h"

namespace ldsm::loop {
namespace {

// A vertex is stored as [quaternion x, y, z, w, translation, log scale].
Sim3d unpackSim3(const double* p) {
  const Eigen::Quaterniond q(p[3], p[0], p[1], p[2]);
  return Sim3d(SO3d(q), Eigen::Vector3d(p[4], p[5], p[6]), std::exp(p[7]));
}

void packSim3(const Sim3d& S, double* p) {
  const Eigen::Quaterniond& q = S.quaternion();
  const Eigen::Vector3d& t = S.translation();
  p[0] = q.x();
  p[1] = q.y();
  p[2] = q.z();
  p[3] = q.w();
  p[4] = t.x();
  p[5] = t.y();
  p[6] = t.z();
  p[7] = std::log(S.scale());
}

constexpr double kMaxRotationStep = kPi;   // radians per manifold step
constexpr double kMaxLogScaleStep = 10.0;  // log scale per manifold step

// Left perturbation S <- exp(d) * S on the 8-number storage. The Jacobians of the cost function
// are given directly in the tangent space (7 columns, the 8th zero), so the plus Jacobian is the
// lifting [I; 0] (and the minus Jacobian its transpose).
class Sim3LeftManifold final : public ceres::Manifold {
 public:
  int AmbientSize() const override { return 8; }
  int TangentSize() const override { return 7; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override {
    // A trial step can be huge (Ceres evaluates Plus(x, -gradient) to test convergence):
    // exp() of it would overflow the scale or wrap the rotation, and inf/NaN is carried on
    // differently by different platforms' arithmetic (it stopped the solver on AArch64). The
    // step is shortened along its direction to at most pi of rotation and e^10 of scale.
    Vector7d d = Eigen::Map<const Vector7d>(delta);
    for (int i = 0; i < 7; ++i)
      if (!std::isfinite(d[i])) d[i] = 0.0;
    const double excess = std::max(
        {d.segment<3>(3).norm() / kMaxRotationStep, std::abs(d[6]) / kMaxLogScaleStep, 1.0});
    d /= excess;
    packSim3(Sim3d::exp(d) * unpackSim3(x), x_plus_delta);
    return true;
  }

  bool PlusJacobian(const double* /*x*/, double* jacobian) const override {
    Eigen::Map<Eigen::Matrix<double, 8, 7, Eigen::RowMajor>> J(jacobian);
    J.setZero();
    J.topRows<7>().setIdentity();
    return true;
  }
  bool Minus(const double* y, const double* x, double* y_minus_x) const override {
    Eigen::Map<Vector7d> d(y_minus_x);
    d = (unpackSim3(y) * unpackSim3(x).inverse()).log();
    return true;
  }
  bool MinusJacobian(const double* /*x*/, double* jacobian) const override {
    Eigen::Map<Eigen::Matrix<double, 7, 8, Eigen::RowMajor>> J(jacobian);
    J.setZero();
    J.leftCols<7>().setIdentity();
    return true;
  }
};

// L^T r with the analytic tangent-space Jacobians of sim3_edge.h.
class EdgeCost final : public ceres::SizedCostFunction<7, 8, 8> {
 public:
  EdgeCost(const Sim3d& measurement, const Matrix7d& sqrt_info)
      : M_(measurement), sqrt_info_(sqrt_info) {}

  bool Evaluate(double const* const* params, double* residuals, double** jacobians) const override {
    const Sim3d S_wi = unpackSim3(params[0]);
    const Sim3d S_wj = unpackSim3(params[1]);
    const bool want_j =
        jacobians != nullptr && (jacobians[0] != nullptr || jacobians[1] != nullptr);
    Matrix7d J_i, J_j;
    const Vector7d r =
        want_j ? sim3EdgeJacobians(M_, S_wi, S_wj, &J_i, &J_j) : sim3EdgeResidual(M_, S_wi, S_wj);
    Eigen::Map<Vector7d> res(residuals);
    res = sqrt_info_ * r;
    if (want_j) {
      for (int k = 0; k < 2; ++k) {
        if (jacobians[k] == nullptr) continue;
        Eigen::Map<Eigen::Matrix<double, 7, 8, Eigen::RowMajor>> J(jacobians[k]);
        J.leftCols<7>() = sqrt_info_ * (k == 0 ? J_i : J_j);
        J.col(7).setZero();
      }
    }
    return r.allFinite();
  }

 private:
  Sim3d M_;
  Matrix7d sqrt_info_;
};

class AbortCallback : public ceres::IterationCallback {
 public:
  explicit AbortCallback(const std::atomic<bool>* flag) : flag_(flag) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& /*summary*/) override {
    if (flag_ != nullptr && flag_->load(std::memory_order_relaxed)) {
      aborted_ = true;
      return ceres::SOLVER_ABORT;
    }
    return ceres::SOLVER_CONTINUE;
  }
  bool aborted() const { return aborted_; }

 private:
  const std::atomic<bool>* flag_;
  bool aborted_ = false;
};

bool finite(const Sim3d& S) {
  return S.matrix().allFinite() && S.scale() > 0.0;
}

}  // namespace

const PoseGraph::Vertex& PoseGraph::at(int id) const {
  const auto it = vertices_.find(id);
  if (it == vertices_.end()) {
    throw InputError("pose graph: no vertex for keyframe " + std::to_string(id));
  }
  return it->second;
}

void PoseGraph::addVertex(int id, const Sim3d& S_world_camera) {
  if (hasVertex(id)) {
    throw InputError("pose graph: keyframe " + std::to_string(id) + " already has a vertex");
  }
  if (!finite(S_world_camera)) {
    throw InputError("pose graph: pose of keyframe " + std::to_string(id) + " is not finite");
  }
  packSim3(S_world_camera, vertices_[id].params.data());
}

void PoseGraph::setVertex(int id, const Sim3d& S_world_camera) {
  at(id);
  if (!finite(S_world_camera)) {
    throw InputError("pose graph: pose of keyframe " + std::to_string(id) + " is not finite");
  }
  packSim3(S_world_camera, vertices_[id].params.data());
}

Sim3d PoseGraph::vertex(int id) const {
  return unpackSim3(at(id).params.data());
}

std::map<int, Sim3d> PoseGraph::vertices() const {
  std::map<int, Sim3d> out;
  for (const auto& [id, v] : vertices_) out.emplace(id, unpackSim3(v.params.data()));
  return out;
}

void PoseGraph::setFixed(int id, bool fixed) {
  at(id);
  vertices_[id].fixed = fixed;
}

bool PoseGraph::isFixed(int id) const {
  return at(id).fixed;
}

void PoseGraph::addEdge(const PoseGraphEdge& edge) {
  const std::string name =
      "pose graph edge " + std::to_string(edge.from_id) + " -> " + std::to_string(edge.to_id);
  at(edge.from_id);
  at(edge.to_id);
  if (edge.from_id == edge.to_id) throw InputError(name + ": connects a vertex to itself");
  if (!finite(edge.S_from_to)) throw InputError(name + ": measurement is not finite");
  const Matrix7d& info = edge.information;
  if (!info.allFinite() || !info.isApprox(info.transpose(), 1e-9)) {
    throw InputError(name + ": information matrix is not finite and symmetric");
  }
  const Eigen::LLT<Matrix7d> llt(info);
  if (llt.info() != Eigen::Success) {
    throw InputError(name + ": information matrix is not positive definite");
  }
  const Matrix7d L = llt.matrixL();
  edges_.push_back(edge);
  sqrt_information_.push_back(L.transpose());
}

void PoseGraph::addEdge(int from_id, int to_id, const Sim3d& S_from_to, double weight,
                        PoseGraphEdgeKind kind) {
  if (!(weight > 0.0) || !std::isfinite(weight)) {
    throw InputError("pose graph edge " + std::to_string(from_id) + " -> " + std::to_string(to_id) +
                     ": weight must be finite and > 0");
  }
  addEdge(PoseGraphEdge{from_id, to_id, S_from_to, weight * Matrix7d::Identity(), kind});
}

Eigen::Matrix<double, 7, 1> PoseGraph::edgeResidual(const PoseGraphEdge& edge) const {
  return sim3EdgeResidual(edge.S_from_to, vertex(edge.from_id), vertex(edge.to_id));
}

double PoseGraph::cost() const {
  double c = 0.0;
  for (const PoseGraphEdge& e : edges_) {
    const Eigen::Matrix<double, 7, 1> r = edgeResidual(e);
    c += 0.5 * r.dot(e.information * r);
  }
  return c;
}

PoseGraphSolveSummary PoseGraph::optimize(const PoseGraphSolveOptions& options) {
  if (options.max_iterations < 1 || !(options.max_time_s > 0.0) ||
      !(options.function_tolerance > 0.0) || !(options.odometry_information_scale > 0.0) ||
      !std::isfinite(options.odometry_information_scale)) {
    throw ConfigError(
        "pose graph: max_iterations >= 1, max_time_s > 0, function_tolerance > 0, "
        "odometry_information_scale finite and > 0");
  }
  const auto t0 = std::chrono::steady_clock::now();
  PoseGraphSolveSummary summary;
  if (edges_.empty()) {
    summary.converged = true;
    summary.message = "no edges";
    return summary;
  }
  if (options.abort != nullptr && options.abort->load(std::memory_order_relaxed)) {
    summary.aborted = true;
    summary.message = "aborted before the first iteration";
    return summary;
  }
  std::map<int, std::array<double, 8>> backup;
  for (const auto& [id, v] : vertices_) backup.emplace(id, v.params);

  ceres::Problem::Options popt;
  popt.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(popt);
  Sim3LeftManifold manifold;
  for (std::size_t k = 0; k < edges_.size(); ++k) {
    const PoseGraphEdge& e = edges_[k];
    const double w = e.kind == PoseGraphEdgeKind::kOdometry
                         ? std::sqrt(options.odometry_information_scale)
                         : 1.0;
    auto* cost = new EdgeCost(e.S_from_to, w * sqrt_information_[k]);
    double* pi = vertices_[e.from_id].params.data();
    double* pj = vertices_[e.to_id].params.data();
    problem.AddResidualBlock(cost, nullptr, pi, pj);
  }
  bool any_fixed = false;
  const int lowest = [&] {
    for (auto& [id, v] : vertices_) {
      if (problem.HasParameterBlock(v.params.data())) return id;
    }
    return -1;
  }();
  for (auto& [id, v] : vertices_) {
    if (!problem.HasParameterBlock(v.params.data())) continue;
    problem.SetManifold(v.params.data(), &manifold);
    if (v.fixed) {
      problem.SetParameterBlockConstant(v.params.data());
      any_fixed = true;
    }
  }
  if (!any_fixed) problem.SetParameterBlockConstant(vertices_[lowest].params.data());

  ceres::Solver::Options so;
  so.minimizer_type = ceres::TRUST_REGION;
  so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  so.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  so.sparse_linear_algebra_library_type =
      ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::SUITE_SPARSE) ? ceres::SUITE_SPARSE
                                                                            : ceres::EIGEN_SPARSE;
  so.max_num_iterations = options.max_iterations;
  so.max_solver_time_in_seconds = options.max_time_s;
  so.function_tolerance = options.function_tolerance;
  so.num_threads = 1;
  so.logging_type = ceres::SILENT;
  so.minimizer_progress_to_stdout = false;
  AbortCallback abort(options.abort);
  so.callbacks.push_back(&abort);

  ceres::Solver::Summary cs;
  ceres::Solve(so, &problem, &cs);
  summary.aborted = abort.aborted() || cs.termination_type == ceres::USER_FAILURE;
  summary.converged = cs.termination_type == ceres::CONVERGENCE;
  summary.iterations = std::max(0, static_cast<int>(cs.iterations.size()) - 1);
  summary.initial_cost = cs.initial_cost;
  summary.final_cost = cs.final_cost;
  summary.message = cs.message;
  bool all_finite = true;
  for (const auto& [id, v] : vertices_) {
    for (const double x : v.params) all_finite = all_finite && std::isfinite(x);
  }
  summary.updated = !summary.aborted && cs.IsSolutionUsable() && all_finite;
  if (!summary.updated) {
    for (auto& [id, v] : vertices_) v.params = backup.at(id);
    summary.final_cost = summary.initial_cost;
  }
  summary.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return summary;
}

}  // namespace ldsm::loop
