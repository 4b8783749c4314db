// Folding a vertex out of the pose graph (PoseGraph::foldVertex). With the edge convention
// S_w_j = S_w_i M exp(r), r ~ N(0, Cov), and the link between the anchor p and the folded vertex
// v written as S_w_v = S_w_p S_pv exp(r_pv):
//   edge v -> x (M_vx):  S_w_x = S_w_p (S_pv M_vx) exp(Ad(M_vx^-1) r_pv) exp(r_vx)
//                        => p -> x, measurement S_pv M_vx,
//                           Cov = Ad(M_vx^-1) Cov_pv Ad(M_vx^-1)^T + Cov_vx;
//   edge x -> v (M_xv):  S_w_p = S_w_x (M_xv S_pv^-1) exp(Ad(S_pv) (r_xv - r_pv))
//                        => x -> p, measurement M_xv S_pv^-1,
//                           Cov = Ad(S_pv) (Cov_xv + Cov_pv) Ad(S_pv)^T.
// A link stored as v -> p (M_vp) is the link p -> v with S_pv = M_vp^-1 and
// Cov_pv = Ad(M_vp) Cov_vp Ad(M_vp)^T (reversing an edge: r_rev = -Ad(M) r).
// For a vertex on a chain (two edges) this is the chain's exact Gaussian marginalisation to first
// order; with more edges the correlations the shared link introduces between the rerouted edges
// are dropped.
#include <Eigen/Cholesky>

#include <cmath>
#include <limits>
#include <string>

#include "ldsm/error.h"
#include "loop/pose_graph.h"

namespace ldsm::loop {
namespace {

Matrix7d inverseSpd(const Matrix7d& A) {
  Matrix7d inv = A.ldlt().solve(Matrix7d::Identity());
  return 0.5 * (inv + inv.transpose());
}

Matrix7d transformed(const Matrix7d& cov, const Matrix7d& A) {
  const Matrix7d out = A * cov * A.transpose();
  return 0.5 * (out + out.transpose());
}

/// The same measurement as an edge in the other direction.
PoseGraphEdge reversed(const PoseGraphEdge& e) {
  PoseGraphEdge r = e;
  std::swap(r.from_id, r.to_id);
  r.S_from_to = e.S_from_to.inverse();
  // Info_rev = Ad(M)^-T Info Ad(M)^-1, from Cov_rev = Ad(M) Cov Ad(M)^T.
  const Matrix7d Ainv = e.S_from_to.inverse().adjoint();
  r.information = transformed(e.information, Ainv.transpose());
  return r;
}

}  // namespace

double informationLogDet(const Matrix7d& information) {
  const Eigen::LDLT<Matrix7d> ldlt(information);
  return ldlt.vectorD().array().max(1e-300).log().sum();
}

void PoseGraph::addOrFuseEdge(PoseGraphEdge edge) {
  for (std::size_t k = 0; k < edges_.size(); ++k) {
    PoseGraphEdge& e = edges_[k];
    if (e.kind != edge.kind) continue;
    const bool same = e.from_id == edge.from_id && e.to_id == edge.to_id;
    if (!same && !(e.from_id == edge.to_id && e.to_id == edge.from_id)) continue;
    if (!same) edge = reversed(edge);
    // Two measurements of one relative pose: with M = M1 exp(x), r1 = x and r2 ~ d + x
    // (d = log(M2^-1 M1)); the minimum of the two costs is x = -(I1 + I2)^-1 I2 d.
    const Vector7d d = (edge.S_from_to.inverse() * e.S_from_to).log();
    const Matrix7d I = e.information + edge.information;
    const Vector7d x = -I.ldlt().solve(edge.information * d);
    e.S_from_to = e.S_from_to * Sim3d::exp(x);
    e.information = 0.5 * (I + I.transpose());
    const Matrix7d L = e.information.llt().matrixL();
    sqrt_information_[k] = L.transpose();
    return;
  }
  addEdge(edge);
}

int PoseGraph::foldVertex(int id, int anchor) {
  at(id);
  at(anchor);
  const std::string name =
      "pose graph: folding keyframe " + std::to_string(id) + " into " + std::to_string(anchor);
  if (id == anchor) throw InputError(name + ": a vertex cannot be folded into itself");
  // The link: the most certain edge between the two.
  int link = -1;
  double best = -std::numeric_limits<double>::infinity();
  std::vector<std::size_t> others;
  for (std::size_t k = 0; k < edges_.size(); ++k) {
    const PoseGraphEdge& e = edges_[k];
    if (e.from_id != id && e.to_id != id) continue;
    const int other = e.from_id == id ? e.to_id : e.from_id;
    if (other != anchor) {
      others.push_back(k);
    } else if (informationLogDet(e.information) > best) {
      best = informationLogDet(e.information);
      link = static_cast<int>(k);
    }
  }
  if (link < 0 && !others.empty()) throw InputError(name + ": the two share no edge");
  std::vector<PoseGraphEdge> rerouted;
  if (link >= 0) {
    const PoseGraphEdge& l = edges_[static_cast<std::size_t>(link)];
    const PoseGraphEdge pv = l.from_id == anchor ? l : reversed(l);  // anchor -> id
    const Sim3d& S_pv = pv.S_from_to;
    const Matrix7d cov_pv = inverseSpd(pv.information);
    for (const std::size_t k : others) {
      const PoseGraphEdge& e = edges_[k];
      PoseGraphEdge n = e;
      const Matrix7d cov = inverseSpd(e.information);
      if (e.from_id == id) {
        n.from_id = anchor;
        n.S_from_to = S_pv * e.S_from_to;
        n.information = inverseSpd(transformed(cov_pv, e.S_from_to.inverse().adjoint()) + cov);
      } else {
        n.to_id = anchor;
        n.S_from_to = e.S_from_to * S_pv.inverse();
        n.information = inverseSpd(transformed(cov + cov_pv, S_pv.adjoint()));
      }
      rerouted.push_back(n);
    }
  }
  // Remove every edge of the vertex, then the vertex, then add the rerouted edges.
  std::size_t w = 0;
  for (std::size_t k = 0; k < edges_.size(); ++k) {
    if (edges_[k].from_id == id || edges_[k].to_id == id) continue;
    edges_[w] = edges_[k];
    sqrt_information_[w] = sqrt_information_[k];
    ++w;
  }
  edges_.resize(w);
  sqrt_information_.resize(w);
  vertices_.erase(id);
  for (const PoseGraphEdge& n : rerouted) addOrFuseEdge(n);
  return static_cast<int>(rerouted.size());
}

void PoseGraph::removeIsolatedVertex(int id) {
  at(id);
  for (const PoseGraphEdge& e : edges_) {
    if (e.from_id == id || e.to_id == id) {
      throw InputError("pose graph: keyframe " + std::to_string(id) +
                       " still has edges and cannot be removed");
    }
  }
  vertices_.erase(id);
}

}  // namespace ldsm::loop
