// The Gaussian prior left behind by marginalised keyframes and points: a quadratic
//   E(delta) = 1/2 delta^T H delta + b^T delta
// over the keyframes still in the window, where delta is each keyframe's state relative to its
// first-estimate linearisation point (which never moves, so the prior stays consistent).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "backend/window_keyframe.h"

namespace ldsm {

class MarginalizationPrior {
 public:
  bool empty() const { return ids_.empty(); }
  /// Keyframe ids the prior involves (block order of H and b).
  const std::vector<int>& ids() const { return ids_; }
  const Eigen::MatrixXd& H() const { return H_; }
  const Eigen::VectorXd& b() const { return b_; }

  /// Block index of a keyframe, adding a zero block when it is new.
  int ensureFrame(int keyframe_id);
  /// Index of a keyframe's block, or -1.
  int indexOf(int keyframe_id) const;

  /// Adds H_add, b_add given over `ids` (8 rows per id), linearised at the keyframes' current
  /// deltas `deltas` (stacked like H_add): stored as a quadratic in delta.
  void add(const std::vector<int>& ids, const Eigen::MatrixXd& H_add, const Eigen::VectorXd& b_add,
           const Eigen::VectorXd& deltas);

  /// Removes a keyframe by Schur complement (its information stays in the remaining blocks).
  void marginalizeFrame(int keyframe_id);

  /// Energy of the prior at the stacked deltas of its frames (in ids() order).
  double energy(const Eigen::VectorXd& deltas) const;

 private:
  std::vector<int> ids_;
  Eigen::MatrixXd H_;
  Eigen::VectorXd b_;
};

}  // namespace ldsm
