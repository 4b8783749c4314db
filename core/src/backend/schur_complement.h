// The depth-eliminated frame block shared by the window solve and the radial envelope step.
#pragma once

#include <Eigen/Core>

namespace ldsm {

/// A -= C diag(inv_d) C^T for a symmetric A and non-negative inv_d, as one symmetric rank-k
/// update (half the products of the general product), then mirrored into the upper triangle.
/// `scaled` receives C diag(sqrt(inv_d)); passing the same matrix every time keeps its memory
/// (several MB for a window) instead of allocating it for each solve.
inline void subtractDepthSchur(Eigen::MatrixXd& A, const Eigen::MatrixXd& C,
                               const Eigen::VectorXd& inv_d, Eigen::MatrixXd& scaled) {
  scaled.noalias() = C * inv_d.cwiseSqrt().asDiagonal();
  A.selfadjointView<Eigen::Lower>().rankUpdate(scaled, -1.0);
  A.triangularView<Eigen::StrictlyUpper>() = A.transpose();
}

inline void subtractDepthSchur(Eigen::MatrixXd& A, const Eigen::MatrixXd& C,
                               const Eigen::VectorXd& inv_d) {
  Eigen::MatrixXd scaled;
  subtractDepthSchur(A, C, inv_d, scaled);
}

}  // namespace ldsm
