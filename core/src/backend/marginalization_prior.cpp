#include "backend/marginalization_prior.h"

#include <Eigen/Cholesky>
#include <algorithm>

namespace ldsm {

int MarginalizationPrior::indexOf(int keyframe_id) const {
  const auto it = std::find(ids_.begin(), ids_.end(), keyframe_id);
  return it == ids_.end() ? -1 : static_cast<int>(it - ids_.begin());
}

int MarginalizationPrior::ensureFrame(int keyframe_id) {
  const int idx = indexOf(keyframe_id);
  if (idx >= 0) return idx;
  const Eigen::Index n = H_.rows();
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n + kFrameParams, n + kFrameParams);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(n + kFrameParams);
  H.topLeftCorner(n, n) = H_;
  b.head(n) = b_;
  H_.swap(H);
  b_.swap(b);
  ids_.push_back(keyframe_id);
  return static_cast<int>(ids_.size()) - 1;
}

void MarginalizationPrior::add(const std::vector<int>& ids, const Eigen::MatrixXd& H_add,
                               const Eigen::VectorXd& b_add, const Eigen::VectorXd& deltas) {
  // A quadratic model linearised at delta_c: gradient g + H (delta - delta_c).
  const Eigen::VectorXd b0 = b_add - H_add * deltas;
  std::vector<int> idx(ids.size());
  for (size_t i = 0; i < ids.size(); ++i) idx[i] = ensureFrame(ids[i]);
  for (size_t i = 0; i < ids.size(); ++i) {
    b_.segment<kFrameParams>(kFrameParams * idx[i]) += b0.segment<kFrameParams>(kFrameParams * i);
    for (size_t j = 0; j < ids.size(); ++j)
      H_.block<kFrameParams, kFrameParams>(kFrameParams * idx[i], kFrameParams * idx[j]) +=
          H_add.block<kFrameParams, kFrameParams>(kFrameParams * i, kFrameParams * j);
  }
}

void MarginalizationPrior::marginalizeFrame(int keyframe_id) {
  const int m = indexOf(keyframe_id);
  if (m < 0) return;
  const Eigen::Index n = H_.rows();
  const Eigen::Index k = kFrameParams;
  // Permute the marginalised block to the end.
  std::vector<Eigen::Index> keep;
  for (Eigen::Index i = 0; i < n; ++i)
    if (i / k != m) keep.push_back(i);
  const Eigen::Index r = static_cast<Eigen::Index>(keep.size());
  Eigen::MatrixXd Hrr(r, r), Hrm(r, k);
  Eigen::VectorXd br(r);
  for (Eigen::Index i = 0; i < r; ++i) {
    br[i] = b_[keep[i]];
    for (Eigen::Index j = 0; j < r; ++j) Hrr(i, j) = H_(keep[i], keep[j]);
    for (Eigen::Index j = 0; j < k; ++j) Hrm(i, j) = H_(keep[i], m * k + j);
  }
  Eigen::MatrixXd Hmm = H_.block(m * k, m * k, k, k);
  const Eigen::VectorXd bm = b_.segment(m * k, k);
  // Jacobi-scaled, slightly regularised inverse: the block can be near singular (gauge).
  Eigen::VectorXd s = Hmm.diagonal().cwiseAbs().cwiseMax(1e-12).cwiseSqrt().cwiseInverse();
  Eigen::MatrixXd Hs = s.asDiagonal() * Hmm * s.asDiagonal();
  Hs.diagonal().array() += 1e-9;
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(Hs);
  const Eigen::MatrixXd Hmm_inv =
      s.asDiagonal() * ldlt.solve(Eigen::MatrixXd::Identity(k, k)) * s.asDiagonal();
  H_ = Hrr - Hrm * Hmm_inv * Hrm.transpose();
  H_ = 0.5 * (H_ + H_.transpose()).eval();
  b_ = br - Hrm * (Hmm_inv * bm);
  ids_.erase(ids_.begin() + m);
}

double MarginalizationPrior::energy(const Eigen::VectorXd& deltas) const {
  if (ids_.empty()) return 0.0;
  return 0.5 * deltas.dot(H_ * deltas) + b_.dot(deltas);
}

}  // namespace ldsm
