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

std::vector<int> refinedParams(const CalibMask& mask) {
  std::vector<int> params;
  for (int p = 0; p < kCalibParams; ++p)
    if (mask[static_cast<size_t>(p)]) params.push_back(p);
  return params;
}

namespace {

/// The rows and columns `params` of M.
Eigen::MatrixXd restricted(const CalibMatrix& M, const std::vector<int>& params) {
  const auto m = static_cast<Eigen::Index>(params.size());
  Eigen::MatrixXd R(m, m);
  for (Eigen::Index i = 0; i < m; ++i)
    for (Eigen::Index j = 0; j < m; ++j)
      R(i, j) = M(params[static_cast<size_t>(i)], params[static_cast<size_t>(j)]);
  return R;
}

/// Whether the LDLT is of a positive definite matrix.
bool positiveDefinite(const Eigen::LDLT<Eigen::MatrixXd>& ldlt) {
  return ldlt.info() == Eigen::Success && ldlt.vectorD().minCoeff() > 0.0;
}

}  // namespace

bool calibrationEnvelopeStep(const Eigen::MatrixXd& H, const Eigen::VectorXd& b,
                             const Eigen::Ref<const Eigen::MatrixXd>& coupling,
                             const std::vector<double>& H_dd, const std::vector<double>& b_d,
                             const CalibrationTerms& terms, const CalibMask& mask,
                             CalibVector* step, CalibMatrix* curvature,
                             Eigen::MatrixXd* schur_scratch) {
  step->setZero();
  curvature->setZero();
  const Eigen::Index dim = H.rows();
  if (dim == 0 || terms.H_fc.rows() != dim || terms.H_fc.cols() != kCalibParams ||
      terms.H_dc.size() != H_dd.size() || b_d.size() != H_dd.size() ||
      coupling.cols() != static_cast<Eigen::Index>(H_dd.size()))
    return false;
  const std::vector<int> active = refinedParams(mask);
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
  const EliminatedDepthTerms& other = terms.other_depths;
  const bool others = other.A.rows() == dim && other.g.size() == dim && other.h.rows() == dim;
  if (others) {
    hcc -= other.hcc;
    bc -= other.bc;
  }
  Eigen::MatrixXd A = H;
  Eigen::MatrixXd local_scratch;
  subtractDepthSchur(A, coupling, inv_d, schur_scratch ? *schur_scratch : local_scratch);
  Eigen::VectorXd g = b;
  g.noalias() -= coupling * wb;
  if (others) {
    A -= other.A;
    g -= other.g;
  }
  // Eliminate the frames. Monocular scale is a null direction of A that c does not touch (the
  // residuals do not depend on it): a tiny relative damping keeps the solve defined.
  double max_diag = 0.0;
  for (Eigen::Index i = 0; i < dim; ++i) max_diag = std::max(max_diag, std::abs(A(i, i)));
  A.diagonal().array() += 1e-9 * max_diag + 1e-12;
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(A);
  const Eigen::VectorXd Ag = ldlt.solve(g);
  const auto m = static_cast<Eigen::Index>(active.size());
  std::vector<Eigen::VectorXd> h(active.size()), Ah(active.size());
  for (size_t j = 0; j < active.size(); ++j) {
    h[j] = terms.H_fc.col(active[j]);
    h[j].noalias() -= coupling * wc.col(active[j]);
    if (others) h[j] -= other.h.col(active[j]);
    Ah[j] = ldlt.solve(h[j]);
  }
  Eigen::MatrixXd S(m, m);
  Eigen::VectorXd r(m);
  for (Eigen::Index i = 0; i < m; ++i) {
    const auto ui = static_cast<size_t>(i);
    r[i] = bc[active[ui]] - h[ui].dot(Ag);
    for (Eigen::Index j = 0; j < m; ++j)
      S(i, j) =
          hcc(active[ui], active[static_cast<size_t>(j)]) - h[ui].dot(Ah[static_cast<size_t>(j)]);
  }
  S = 0.5 * (S + S.transpose()).eval();
  if (!S.allFinite() || !r.allFinite()) return false;
  const Eigen::LDLT<Eigen::MatrixXd> schur(S);
  if (!positiveDefinite(schur)) return false;
  const Eigen::VectorXd x = -schur.solve(r);
  if (!x.allFinite()) return false;
  for (Eigen::Index i = 0; i < m; ++i) {
    const auto ui = static_cast<size_t>(i);
    (*step)[active[ui]] = x[i];
    for (Eigen::Index j = 0; j < m; ++j)
      (*curvature)(active[ui], active[static_cast<size_t>(j)]) = S(i, j);
  }
  return true;
}

CalibrationRefinement::CalibrationRefinement(const CalibrationRefinementConfig& config,
                                             int window_keyframes)
    : config_(config), window_keyframes_(std::max(1, window_keyframes)) {
  mask_ = {config.refine_radial, config.refine_focal, config.refine_principal_point,
           config.refine_principal_point};
  refined_ = refinedParams(mask_);
  dead_band_ << config.radial_dead_band, config.focal_dead_band, config.principal_point_dead_band,
      config.principal_point_dead_band;
  max_ << config.radial_max, config.focal_max, config.principal_point_max,
      config.principal_point_max;
  significance_ << config.radial_significance, config.focal_significance,
      config.principal_point_significance, config.principal_point_significance;
}

CalibVector CalibrationRefinement::sigma() const {
  CalibVector s = CalibVector::Zero();
  if (windows_ == 0 || refined_.empty()) return s;
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(restricted(weight_, refined_));
  if (!positiveDefinite(ldlt)) return s;
  const auto m = static_cast<Eigen::Index>(refined_.size());
  const Eigen::MatrixXd cov = ldlt.solve(Eigen::MatrixXd::Identity(m, m));
  for (Eigen::Index i = 0; i < m; ++i) s[refined_[static_cast<size_t>(i)]] = std::sqrt(cov(i, i));
  return s;
}

CalibVector CalibrationRefinement::realisticSigma() const {
  CalibVector s = sigma();
  if (scatter_weight_ <= 0.0) return s;
  for (const int p : refined_)
    s[p] *= std::sqrt(window_keyframes_ * std::max(1.0, scatter_[p] / scatter_weight_));
  return s;
}

void CalibrationRefinement::startAt(double focal_log_scale, double cx_shift, double cy_shift) {
  const double c[] = {focal_log_scale, cx_shift, cy_shift};
  const int params[] = {kCalibFocal, kCalibCx, kCalibCy};
  for (int i = 0; i < 3; ++i) {
    const int p = params[i];
    const auto u = static_cast<size_t>(p);
    estimate_[p] = c[i];
    applied_[p] = c[i];
    engaged_[u] = c[i] != 0.0;
  }
}

void CalibrationRefinement::addWindowStep(const CalibVector& step, const CalibMatrix& curvature) {
  if (refined_.empty() || !step.allFinite() || !curvature.allFinite()) return;
  // Only the refined parameters take part; their curvature block must be positive definite.
  const Eigen::MatrixXd C = restricted(curvature, refined_);
  if (!positiveDefinite(Eigen::LDLT<Eigen::MatrixXd>(C))) return;
  // Before the first window the estimate is the configured camera (0), held with one window's
  // weight: the first window moves it half way. (With four windows' weight the estimate took
  // 100 keyframes to find a principal point told 10 px off; with none, single noisy windows
  // swung it.)
  constexpr double kFirstWindowWeight = 1.0;
  const auto m = static_cast<Eigen::Index>(refined_.size());
  Eigen::MatrixXd W =
      windows_ == 0 ? Eigen::MatrixXd(kFirstWindowWeight * C) : restricted(weight_, refined_);
  W = config_.memory * W + C;
  // estimate += W^-1 C (measurement - estimate) with measurement = applied + step.
  Eigen::VectorXd innovation(m);
  for (Eigen::Index i = 0; i < m; ++i) {
    const int p = refined_[static_cast<size_t>(i)];
    innovation[i] = applied_[p] + step[p] - estimate_[p];
  }
  const Eigen::MatrixXd gain = W.ldlt().solve(C);
  const Eigen::VectorXd delta = gain * innovation;
  if (!delta.allFinite()) return;
  // The window's own formal deviation of each parameter (marginal: C^-1), to measure how far the
  // windows really scatter in its units.
  const Eigen::MatrixXd window_cov = C.ldlt().solve(Eigen::MatrixXd::Identity(m, m));
  scatter_weight_ = config_.memory * scatter_weight_ + 1.0;
  for (Eigen::Index i = 0; i < m; ++i) {
    const int p = refined_[static_cast<size_t>(i)];
    const double var = window_cov(i, i);
    const double z2 = var > 0.0 ? innovation[i] * innovation[i] / var : 0.0;
    scatter_[p] = config_.memory * scatter_[p] + (std::isfinite(z2) ? z2 : 0.0);
  }
  applied_before_[static_cast<size_t>(windows_ % kQuietWindows)] = applied_;
  ++windows_;
  for (Eigen::Index i = 0; i < m; ++i) {
    const int p = refined_[static_cast<size_t>(i)];
    for (Eigen::Index j = 0; j < m; ++j) weight_(p, refined_[static_cast<size_t>(j)]) = W(i, j);
    estimate_[p] = std::clamp(estimate_[p] + delta[i], -max_[p], max_[p]);
  }
  const CalibVector realistic = realisticSigma();
  for (const int p : refined_) {
    const auto u = static_cast<size_t>(p);
    const double settle = 1.0 + config_.settle_windows / static_cast<double>(windows_);
    const double magnitude = std::abs(estimate_[p]);
    if (magnitude > settle * dead_band_[p] && magnitude > significance_[p] * realistic[p])
      engaged_[u] = true;
    else if (std::abs(estimate_[p]) < 0.5 * dead_band_[p])
      engaged_[u] = false;
    applied_[p] = engaged_[u] ? estimate_[p] : 0.0;
  }
}

bool CalibrationRefinement::settling() const {
  if (refined_.empty()) return false;
  if (windows_ == 0) return true;
  // The correction applied kQuietWindows windows ago (before the first window while fewer).
  const CalibVector& ago = applied_before_[static_cast<size_t>(
      windows_ >= kQuietWindows ? windows_ % kQuietWindows : 0)];
  for (const int p : refined_)
    if (std::abs(applied_[p] - ago[p]) > kMoveOfDeadBand * dead_band_[p]) return true;
  return false;
}

}  // namespace ldsm
