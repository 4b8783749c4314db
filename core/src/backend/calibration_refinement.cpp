#include "backend/calibration_refinement.h"

#include "backend/schur_complement.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

namespace ldsm {

PinholeIntrinsics correctedIntrinsics(const PinholeIntrinsics& base, const CalibVector& c) {
  PinholeIntrinsics k = base;
  const double scale = std::exp(c[kCalibFocal]);
  k.fx = base.fx * scale;
  k.fy = base.fy * scale;
  k.cx = base.cx + c[kCalibCx];
  k.cy = base.cy + c[kCalibCy];
  return k;
}

bool calibrationEnvelopeStep(const Eigen::MatrixXd& H, const Eigen::VectorXd& b,
                             const Eigen::MatrixXd& coupling, const std::vector<double>& H_dd,
                             const std::vector<double>& b_d, const CalibrationTerms& terms,
                             const CalibMask& mask, CalibVector* step, CalibMatrix* curvature) {
  step->setZero();
  curvature->setZero();
  const Eigen::Index dim = H.rows();
  if (dim == 0 || terms.H_fc.rows() != dim || terms.H_fc.cols() != kCalibParams ||
      terms.H_dc.size() != H_dd.size() || b_d.size() != H_dd.size() ||
      coupling.cols() != static_cast<Eigen::Index>(H_dd.size()))
    return false;
  std::vector<int> active;
  for (int p = 0; p < kCalibParams; ++p)
    if (mask[static_cast<size_t>(p)]) active.push_back(p);
  if (active.empty()) return false;
  // Eliminate the depths (each couples to the frames and to c).
  const Eigen::Index np = coupling.cols();
  Eigen::VectorXd inv_d(np), wb(np);
  Eigen::MatrixXd wc(np, kCalibParams);
  CalibMatrix hcc = terms.H_cc;
  CalibVector bc = terms.b_c;
  for (Eigen::Index i = 0; i < np; ++i) {
    const auto u = static_cast<size_t>(i);
    inv_d[i] = H_dd[u] > 1e-10 ? 1.0 / H_dd[u] : 0.0;
    wb[i] = b_d[u] * inv_d[i];
    for (int p : active) wc(i, p) = terms.H_dc[u][p] * inv_d[i];
    for (int p : active) {
      bc[p] -= terms.H_dc[u][p] * wb[i];
      for (int q : active) hcc(p, q) -= terms.H_dc[u][p] * wc(i, q);
    }
  }
  Eigen::MatrixXd A = H;
  subtractDepthSchur(A, coupling, inv_d);
  Eigen::VectorXd g = b;
  g.noalias() -= coupling * wb;
  // Eliminate the frames. Monocular scale is a null direction of A that c does not touch (the
  // residuals do not depend on it): a tiny relative damping keeps the solve defined.
  double max_diag = 0.0;
  for (Eigen::Index i = 0; i < dim; ++i) max_diag = std::max(max_diag, std::abs(A(i, i)));
  A.diagonal().array() += 1e-9 * max_diag + 1e-12;
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(A);
  const Eigen::VectorXd Ag = ldlt.solve(g);
  const int m = static_cast<int>(active.size());
  std::vector<Eigen::VectorXd> h(static_cast<size_t>(m)), Ah(static_cast<size_t>(m));
  for (int j = 0; j < m; ++j) {
    const auto uj = static_cast<size_t>(j);
    h[uj] = terms.H_fc.col(active[uj]);
    h[uj].noalias() -= coupling * wc.col(active[uj]);
    Ah[uj] = ldlt.solve(h[uj]);
  }
  Eigen::MatrixXd S(m, m);
  Eigen::VectorXd r(m);
  for (int i = 0; i < m; ++i) {
    const auto ui = static_cast<size_t>(i);
    r[i] = bc[active[ui]] - h[ui].dot(Ag);
    for (int j = 0; j < m; ++j)
      S(i, j) =
          hcc(active[ui], active[static_cast<size_t>(j)]) - h[ui].dot(Ah[static_cast<size_t>(j)]);
  }
  S = 0.5 * (S + S.transpose()).eval();
  if (!S.allFinite() || !r.allFinite()) return false;
  Eigen::VectorXd x(m);
  if (m == 1) {
    if (!(S(0, 0) > 0.0)) return false;
    x[0] = -r[0] / S(0, 0);
  } else {
    const Eigen::LLT<Eigen::MatrixXd> llt(S);
    if (llt.info() != Eigen::Success) return false;
    x = -llt.solve(r);
  }
  if (!x.allFinite()) return false;
  for (int i = 0; i < m; ++i) {
    const auto ui = static_cast<size_t>(i);
    (*step)[active[ui]] = x[i];
    for (int j = 0; j < m; ++j) (*curvature)(active[ui], active[static_cast<size_t>(j)]) = S(i, j);
  }
  return true;
}

CalibrationRefinement::CalibrationRefinement(const CalibrationRefinementConfig& config)
    : config_(config) {
  mask_ = {config.refine_radial, config.refine_focal, config.refine_principal_point,
           config.refine_principal_point};
  dead_band_ << config.radial_dead_band, config.focal_dead_band, config.principal_point_dead_band,
      config.principal_point_dead_band;
  max_ << config.radial_max, config.focal_max, config.principal_point_max,
      config.principal_point_max;
}

CalibVector CalibrationRefinement::sigma() const {
  CalibVector s = CalibVector::Zero();
  if (windows_ == 0) return s;
  std::vector<int> active;
  for (int p = 0; p < kCalibParams; ++p)
    if (mask_[static_cast<size_t>(p)]) active.push_back(p);
  const int m = static_cast<int>(active.size());
  Eigen::MatrixXd W(m, m);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j)
      W(i, j) = weight_(active[static_cast<size_t>(i)], active[static_cast<size_t>(j)]);
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(W);
  if (ldlt.info() != Eigen::Success) return s;
  const Eigen::MatrixXd cov = ldlt.solve(Eigen::MatrixXd::Identity(m, m));
  for (int i = 0; i < m; ++i)
    s[active[static_cast<size_t>(i)]] = std::sqrt(std::max(0.0, cov(i, i)));
  return s;
}

void CalibrationRefinement::addWindowStep(const CalibVector& step, const CalibMatrix& curvature) {
  if (!active() || !step.allFinite() || !curvature.allFinite()) return;
  // Only the refined parameters take part; their curvature block must be positive definite.
  CalibMatrix C = CalibMatrix::Zero();
  for (int p = 0; p < kCalibParams; ++p)
    for (int q = 0; q < kCalibParams; ++q)
      if (mask_[static_cast<size_t>(p)] && mask_[static_cast<size_t>(q)]) C(p, q) = curvature(p, q);
  for (int p = 0; p < kCalibParams; ++p)
    if (mask_[static_cast<size_t>(p)] && !(C(p, p) > 0.0)) return;
  CalibMatrix Cr = C;
  for (int p = 0; p < kCalibParams; ++p)
    if (!mask_[static_cast<size_t>(p)]) Cr(p, p) = 1.0;
  if (Eigen::LLT<CalibMatrix>(Cr).info() != Eigen::Success) return;

  CalibVector measurement = applied_ + step;
  // The first window counts as much as a few: one window alone does not swing the estimate.
  constexpr double kFirstWindowWeight = 4.0;
  if (windows_ == 0) weight_ = kFirstWindowWeight * C;
  weight_ = config_.memory * weight_ + C;
  // estimate += W^-1 C (measurement - estimate), over the refined parameters.
  CalibMatrix Wr = weight_;
  for (int p = 0; p < kCalibParams; ++p)
    if (!mask_[static_cast<size_t>(p)]) {
      Wr.row(p).setZero();
      Wr.col(p).setZero();
      Wr(p, p) = 1.0;
      measurement[p] = 0.0;
    }
  int refined = 0, only = 0;
  for (int p = 0; p < kCalibParams; ++p)
    if (mask_[static_cast<size_t>(p)]) ++refined, only = p;
  if (refined == 1) {
    // One parameter: the scalar form of the same update.
    estimate_[only] += C(only, only) / weight_(only, only) * (measurement[only] - estimate_[only]);
  } else {
    const CalibVector delta = Wr.ldlt().solve(C * (measurement - estimate_));
    if (!delta.allFinite()) return;
    estimate_ += delta;
  }
  ++windows_;
  for (int p = 0; p < kCalibParams; ++p) {
    const auto u = static_cast<size_t>(p);
    if (!mask_[u]) {
      estimate_[p] = applied_[p] = 0.0;
      continue;
    }
    estimate_[p] = std::clamp(estimate_[p], -max_[p], max_[p]);
    if (std::abs(estimate_[p]) > dead_band_[p])
      engaged_[u] = true;
    else if (std::abs(estimate_[p]) < 0.5 * dead_band_[p])
      engaged_[u] = false;
    applied_[p] = engaged_[u] ? estimate_[p] : 0.0;
  }
}

}  // namespace ldsm
