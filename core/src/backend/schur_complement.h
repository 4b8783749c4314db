// The depth-eliminated frame block shared by the window solve and the radial envelope step.
#pragma once

#include <Eigen/Core>

#include "backend/kept_columns.h"

namespace ldsm {

/// A -= C diag(inv_d) C^T for a symmetric A and non-negative inv_d, as one symmetric rank-k
/// update (half the products of the general product), then mirrored into the upper triangle.
/// C diag(sqrt(inv_d)) is written into the first columns of `scratch` (keptColumns()): passing
/// the same matrix every time keeps its memory (about 1 MB for a window) instead of allocating it
/// for each solve, also when the number of points changes from one keyframe to the next.
inline void subtractDepthSchur(Eigen::MatrixXd& A, const Eigen::Ref<const Eigen::MatrixXd>& C,
                               const Eigen::VectorXd& inv_d, Eigen::MatrixXd& scratch) {
  auto scaled = keptColumns(scratch, C.rows(), C.cols());
  scaled.noalias() = C * inv_d.cwiseSqrt().asDiagonal();
  A.selfadjointView<Eigen::Lower>().rankUpdate(scaled, -1.0);
  A.triangularView<Eigen::StrictlyUpper>() = A.transpose();
}

inline void subtractDepthSchur(Eigen::MatrixXd& A, const Eigen::Ref<const Eigen::MatrixXd>& C,
                               const Eigen::VectorXd& inv_d) {
  Eigen::MatrixXd scaled;
  subtractDepthSchur(A, C, inv_d, scaled);
}

}  // namespace ldsm
