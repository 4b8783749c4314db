#include "backend/radial_correction.h"

#include "backend/schur_complement.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

namespace ldsm {

bool radialEnvelopeStep(const Eigen::MatrixXd& H, const Eigen::VectorXd& b,
                        const Eigen::MatrixXd& coupling, const std::vector<double>& H_dd,
                        const std::vector<double>& b_d, const RadialTerms& terms, double* step,
                        double* curvature) {
  *step = *curvature = 0.0;
  const Eigen::Index dim = H.rows();
  if (dim == 0 || terms.H_fk.size() != dim || terms.H_dk.size() != H_dd.size() ||
      b_d.size() != H_dd.size() || coupling.cols() != static_cast<Eigen::Index>(H_dd.size()))
    return false;
  // Eliminate the depths (each couples to the frames and to k).
  const Eigen::Index np = coupling.cols();
  Eigen::VectorXd inv_d(np), wk(np), wb(np);
  double hkk = terms.H_kk, bk = terms.b_k;
  for (Eigen::Index i = 0; i < np; ++i) {
    const auto u = static_cast<size_t>(i);
    inv_d[i] = H_dd[u] > 1e-10 ? 1.0 / H_dd[u] : 0.0;
    wk[i] = terms.H_dk[u] * inv_d[i];
    wb[i] = b_d[u] * inv_d[i];
    hkk -= terms.H_dk[u] * wk[i];
    bk -= terms.H_dk[u] * wb[i];
  }
  Eigen::MatrixXd A = H;
  subtractDepthSchur(A, coupling, inv_d);
  Eigen::VectorXd h = terms.H_fk, g = b;
  h.noalias() -= coupling * wk;
  g.noalias() -= coupling * wb;
  // Eliminate the frames. Monocular scale is a null direction of A that k does not touch (the
  // residuals do not depend on it): a tiny relative damping keeps the solve defined.
  double max_diag = 0.0;
  for (Eigen::Index i = 0; i < dim; ++i) max_diag = std::max(max_diag, std::abs(A(i, i)));
  A.diagonal().array() += 1e-9 * max_diag + 1e-12;
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(A);
  const double c = hkk - h.dot(ldlt.solve(h));
  const double r = bk - h.dot(ldlt.solve(g));
  if (!(c > 0.0) || !std::isfinite(c) || !std::isfinite(r)) return false;
  *step = -r / c;
  *curvature = c;
  return true;
}

void RadialRefinement::addWindowStep(double step, double curvature) {
  if (!config_.refine_radial || !(curvature > 0.0) || !std::isfinite(step) ||
      !std::isfinite(curvature))
    return;
  const double measurement = applied_ + step;
  // The first window counts as much as a few: one window alone does not swing the estimate.
  constexpr double kFirstWindowWeight = 4.0;
  if (windows_ == 0) weight_ = kFirstWindowWeight * curvature;
  weight_ = config_.radial_memory * weight_ + curvature;
  estimate_ += curvature / weight_ * (measurement - estimate_);
  estimate_ = std::clamp(estimate_, -config_.radial_max, config_.radial_max);
  ++windows_;
  if (std::abs(estimate_) > config_.radial_dead_band)
    engaged_ = true;
  else if (std::abs(estimate_) < 0.5 * config_.radial_dead_band)
    engaged_ = false;
  applied_ = engaged_ ? estimate_ : 0.0;
}

}  // namespace ldsm
