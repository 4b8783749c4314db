// Residual and analytic Jacobians of a Sim(3) pose-graph edge. With world-from-camera vertices
// S_w_i, S_w_j and the measurement M = S_i_j (camera j -> camera i):
//   r = log(M^-1 * S_w_i^-1 * S_w_j) in R^7 ([rho, phi, sigma]),
// and for left perturbations S_w <- exp(d) * S_w (the pose graph's manifold):
//   E(d_j) = E * exp(Ad(S_w_j^-1) d_j)   =>  dr/dd_j =  Jr^-1(r) * Ad(S_w_j^-1),
//   E(d_i) = E * exp(-Ad(S_w_j^-1) d_i)  =>  dr/dd_i = -Jr^-1(r) * Ad(S_w_j^-1).
// Jr^-1 is Sim3's Bernoulli series (ad^8); its truncation error scales with
// |(phi, sigma)|^9, negligible for residual rotations below ~1 rad and scale ratios below e.
#pragma once

#include <Eigen/Core>

#include "math/sim3.h"

namespace ldsm::loop {

using Vector7d = Eigen::Matrix<double, 7, 1>;
using Matrix7d = Eigen::Matrix<double, 7, 7>;

/// The edge residual r = log(M^-1 S_w_i^-1 S_w_j).
inline Vector7d sim3EdgeResidual(const Sim3d& M, const Sim3d& S_wi, const Sim3d& S_wj) {
  return (M.inverse() * S_wi.inverse() * S_wj).log();
}

/// Residual and its Jacobians with respect to left perturbations of S_w_i and S_w_j.
inline Vector7d sim3EdgeJacobians(const Sim3d& M, const Sim3d& S_wi, const Sim3d& S_wj,
                                  Matrix7d* J_i, Matrix7d* J_j) {
  const Vector7d r = sim3EdgeResidual(M, S_wi, S_wj);
  const Matrix7d Jj = Sim3d::rightJacobianInverse(r) * S_wj.inverse().adjoint();
  if (J_j != nullptr) *J_j = Jj;
  if (J_i != nullptr) *J_i = -Jj;
  return r;
}

}  // namespace ldsm::loop
