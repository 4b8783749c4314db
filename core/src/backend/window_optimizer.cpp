#include "backend/window_optimizer.h"

#include "backend/schur_complement.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

namespace ldsm {
namespace {

/// f(i, j) for every pair of touched frame blocks with i >= j, j outer: the lower blocks of
/// c c^T for a point's frame coupling c, which is non-zero only in its host's and its inlier
/// targets' blocks (the upper triangle is mirrored once afterwards).
template <typename F>
void forTouchedLowerBlocks(const std::vector<char>& touched, F&& f) {
  const int n = static_cast<int>(touched.size());
  for (int j = 0; j < n; ++j) {
    if (!touched[static_cast<size_t>(j)]) continue;
    for (int i = j; i < n; ++i)
      if (touched[static_cast<size_t>(i)]) f(i, j);
  }
}

using Mat16 = Eigen::Matrix<double, 16, 16>;
using Vec16 = Eigen::Matrix<double, 16, 1>;
using Map10x16 = Eigen::Matrix<double, kRelParams, 16>;

/// d(relative parameters) / d(host params, target params): eps = delta_t - Ad(T_th) delta_h.
Map10x16 relativeToAbsolute(const Eigen::Matrix<double, 6, 6>& Ad) {
  Map10x16 P = Map10x16::Zero();
  P.block<6, 6>(0, 0) = -Ad;
  P.block<6, 6>(0, 8) = Eigen::Matrix<double, 6, 6>::Identity();
  P(6, 6) = 1.0;   // a_h
  P(7, 7) = 1.0;   // b_h
  P(8, 14) = 1.0;  // a_t
  P(9, 15) = 1.0;  // b_t
  return P;
}

/// The coupling of a depth to (host, target) parameters from its relative-parameter coupling,
/// the transpose of relativeToAbsolute() applied without the dense product.
void addCoupling(const Eigen::Matrix<double, 6, 6>& Ad, const Eigen::Ref<const RelVector>& c_rel,
                 int h, int t, Eigen::Ref<Eigen::VectorXd> c) {
  c.segment<6>(kFrameParams * h).noalias() -= Ad.transpose() * c_rel.head<6>();
  c.segment<2>(kFrameParams * h + 6) += c_rel.segment<2>(6);
  c.segment<6>(kFrameParams * t) += c_rel.head<6>();
  c.segment<2>(kFrameParams * t + 6) += c_rel.segment<2>(8);
}

void addPairBlocks(int h, int t, const Mat16& H16, const Vec16& b16, Eigen::MatrixXd& H,
                   Eigen::VectorXd& b) {
  const int k = kFrameParams;
  H.block<k, k>(k * h, k * h) += H16.block<k, k>(0, 0);
  H.block<k, k>(k * h, k * t) += H16.block<k, k>(0, k);
  H.block<k, k>(k * t, k * h) += H16.block<k, k>(k, 0);
  H.block<k, k>(k * t, k * t) += H16.block<k, k>(k, k);
  b.segment<k>(k * h) += b16.head<k>();
  b.segment<k>(k * t) += b16.tail<k>();
}

Eigen::VectorXd stackedDeltas(const std::vector<WindowKeyframe*>& window) {
  Eigen::VectorXd d(kFrameParams * window.size());
  for (size_t i = 0; i < window.size(); ++i)
    d.segment<kFrameParams>(kFrameParams * i) = window[i]->delta();
  return d;
}

std::vector<int> windowIds(const std::vector<WindowKeyframe*>& window) {
  std::vector<int> ids;
  for (const auto* kf : window) ids.push_back(kf->id());
  return ids;
}

/// Adds the pairs' accumulated blocks, mapped onto (host, target) parameters, to H and b.
void addPairAccumulators(int n, const std::vector<PairAccumulator>& acc,
                         const std::vector<FramePairPrecalc>& pairs,
                         const std::vector<Eigen::Matrix<double, 6, 6>>& adjoints,
                         Eigen::MatrixXd& H, Eigen::VectorXd& b) {
  RelMatrix Hr;
  RelVector br;
  for (int h = 0; h < n; ++h)
    for (int t = 0; t < n; ++t) {
      const size_t pi = static_cast<size_t>(h) * n + t;
      if (h == t || acc[pi].count() == 0) continue;
      acc[pi].reduce(pairs[pi], Hr, br);
      const Map10x16 P = relativeToAbsolute(adjoints[pi]);
      const Mat16 H16 = P.transpose() * Hr * P;
      const Vec16 b16 = P.transpose() * br;
      addPairBlocks(h, t, H16, b16, H, b);
    }
}

void resetPairAccumulators(size_t count, std::vector<PairAccumulator>& acc) {
  acc.resize(count);
  for (auto& a : acc) a.reset();
}

}  // namespace

void WindowOptimizer::framePairs(const std::vector<WindowKeyframe*>& window,
                                 std::vector<FramePairPrecalc>& pairs) const {
  const size_t n = window.size();
  pairs.resize(n * n);
  for (size_t i = 0; i < n; ++i) window[i]->window_index = static_cast<int>(i);
  for (size_t h = 0; h < n; ++h)
    for (size_t t = 0; t < n; ++t) {
      if (h == t || !window[t]->hasImage()) continue;
      pairs[h * n + t].set(*window[h], *window[t], camera_);
      pairs[h * n + t].radial_k = static_cast<float>(radial_k_);
    }
}

void WindowOptimizer::precalcPairs(const std::vector<WindowKeyframe*>& window) {
  const size_t n = window.size();
  framePairs(window, pairs_);
  adjoints_.resize(n * n);
  for (size_t h = 0; h < n; ++h)
    for (size_t t = 0; t < n; ++t) {
      // Every pair's adjoint, also towards a keyframe without an image (a reactivated map
      // keyframe, never a residual's target): the pair sums multiply it by their zero terms, and
      // an adjoint left from an earlier window, or never written, could be anything, NaN too.
      if (h == t) {
        adjoints_[h * n + t].setIdentity();
        continue;
      }
      adjoints_[h * n + t] = (window[t]->T_c_w_eval * window[h]->T_c_w_eval.inverse()).adjoint();
    }
}

FrameVector WindowOptimizer::anchorWeights(const WindowKeyframe& kf, double anchor) {
  FrameVector w = FrameVector::Constant(anchor);
  if (!kf.is_gauge_anchor && !kf.is_reactivated && kf.anchor_affine_weight > 0.0)
    w.tail<2>().setConstant(kf.anchor_affine_weight);
  return w;
}

double WindowOptimizer::addPriors(const std::vector<WindowKeyframe*>& window,
                                  const MarginalizationPrior& prior, Eigen::MatrixXd* H,
                                  Eigen::VectorXd* b) const {
  const int k = kFrameParams;
  double energy = 0.0;
  for (size_t i = 0; i < window.size(); ++i) {
    const WindowKeyframe& kf = *window[i];
    const double a = kf.aff.a, bb = kf.aff.b;
    energy += 0.5 * (settings_.affine_prior_a * a * a + settings_.affine_prior_b * bb * bb);
    if (H) {
      (*H)(k * i + 6, k * i + 6) += settings_.affine_prior_a;
      (*H)(k * i + 7, k * i + 7) += settings_.affine_prior_b;
      (*b)[k * i + 6] += settings_.affine_prior_a * a;
      (*b)[k * i + 7] += settings_.affine_prior_b * bb;
    }
    const double anchor = kf.is_gauge_anchor ? settings_.gauge_anchor_weight
                          : kf.is_reactivated
                              ? (settings_.reactivated_weight > 0.0 ? settings_.reactivated_weight
                                                                    : settings_.gauge_anchor_weight)
                              : kf.anchor_weight;
    if (anchor > 0.0) {
      // The gauge anchor: pose and affine brightness stay at their first estimate. Without the
      // affine part, the offsets b of all keyframes drift together (the cost hardly changes when
      // every b moves by the same amount; on kitti00_200 by -500 grey levels in 200 frames), away
      // from the first estimates their Jacobians are taken at. A reactivated map keyframe is held
      // the same way: the map's estimate.
      const FrameVector w = anchorWeights(kf, anchor);
      const FrameVector d = kf.delta();
      energy += 0.5 * d.dot(w.cwiseProduct(d));
      if (H) {
        H->block<k, k>(k * i, k * i).diagonal() += w;
        b->segment<k>(k * i) += w.cwiseProduct(d);
      }
    }
  }
  return energy + addMarginalizationPrior(window, prior, 1.0, H, b);
}

double WindowOptimizer::addMarginalizationPrior(const std::vector<WindowKeyframe*>& window,
                                                const MarginalizationPrior& prior, double sign,
                                                Eigen::MatrixXd* H, Eigen::VectorXd* b) const {
  if (prior.empty()) return 0.0;
  const int k = kFrameParams;
  // Gather the prior onto the window's block order.
  const auto& ids = prior.ids();
  std::vector<int> at(ids.size(), -1);
  Eigen::VectorXd deltas(k * ids.size());
  for (size_t j = 0; j < ids.size(); ++j) {
    for (size_t i = 0; i < window.size(); ++i)
      if (window[i]->id() == ids[j]) at[j] = static_cast<int>(i);
    deltas.segment<k>(k * j) = at[j] >= 0 ? window[at[j]]->delta() : FrameVector::Zero().eval();
  }
  if (H) {
    const Eigen::VectorXd g = prior.b() + prior.H() * deltas;
    for (size_t j = 0; j < ids.size(); ++j) {
      if (at[j] < 0) continue;
      b->segment<k>(k * at[j]) += sign * g.segment<k>(k * j);
      for (size_t l = 0; l < ids.size(); ++l)
        if (at[l] >= 0)
          H->block<k, k>(k * at[j], k * at[l]) += sign * prior.H().block<k, k>(k * j, k * l);
    }
  }
  return sign * prior.energy(deltas);
}

void WindowOptimizer::linearize(const std::vector<WindowKeyframe*>& window,
                                const MarginalizationPrior& prior, System& sys) {
  const int n = static_cast<int>(window.size());
  const int dim = kFrameParams * n;
  sys.H.setZero(dim, dim);
  sys.b.setZero(dim);
  sys.points.clear();
  sys.H_dd.clear();
  sys.b_d.clear();
  sys.inliers = sys.outliers = 0;
  sys.inlier_energy = 0.0;
  resetPairAccumulators(static_cast<size_t>(n) * n, pair_acc_);

  size_t num_points = 0;
  Eigen::Index num_columns = 0;
  host_terms_.resize(static_cast<size_t>(n));
  for (int h = 0; h < n; ++h) {
    HostTerms& ht = host_terms_[static_cast<size_t>(h)];
    ht.first_point = num_points;
    ht.first_column = num_columns;
    for (const auto& pt : window[static_cast<size_t>(h)]->points) num_columns += pt->fixed ? 0 : 1;
    num_points += window[static_cast<size_t>(h)]->points.size();
  }
  sys.resetCoupling(dim, num_columns);

  // The hosts' points are independent (each writes its own points, its own pair blocks and its
  // own coupling columns), so they are linearised as parallel tasks, one per host; the energies
  // are then summed in the one-thread order (host, point, residual) from what the tasks kept.
  sys.points.resize(num_points);
  sys.column.resize(num_points);
  sys.H_dd.resize(num_points);
  sys.b_d.resize(num_points);
  const auto linearizeHost = [&](int h) {
    HostTerms& ht = host_terms_[static_cast<size_t>(h)];
    ht.energies.clear();
    ht.inlier.clear();
    ht.outliers = 0;
    size_t index = ht.first_point;
    Eigen::Index next_column = ht.first_column;
    for (auto& pt : window[static_cast<size_t>(h)]->points) {
      ActivePoint& p = *pt;
      const Eigen::Index col = p.fixed ? -1 : next_column++;
      double H_dd = 0.0, b_d = 0.0;
      int inl = 0;
      const Eigen::Vector2f host = hostPixel(p);
      for (auto& res : p.residuals) {
        const int t = res.target->window_index;
        const size_t pi = static_cast<size_t>(h) * n + t;
        ResidualAccumulator acc;
        acc.pair = &pair_acc_[pi];
        const float e = evaluateResidual(p, host, res, pairs_[pi], settings_.residual, &acc);
        if (res.state == ResidualState::Inlier) {
          ht.energies.push_back(e);
          ht.inlier.push_back(1);
          ++inl;
          H_dd += acc.H_dd;
          b_d += acc.b_d;
          if (col >= 0) addCoupling(adjoints_[pi], acc.coupling, h, t, sys.coupling().col(col));
        } else {
          ht.energies.push_back(outlierEnergy(pairs_[pi], settings_.residual));
          ht.inlier.push_back(0);
          if (res.state == ResidualState::Outlier) ++ht.outliers;
        }
      }
      p.hessian_idepth = static_cast<float>(H_dd);
      p.gradient_idepth = static_cast<float>(b_d);
      p.inlier_residuals = inl;
      sys.points[index] = &p;
      sys.column[index] = col;
      sys.H_dd[index] = H_dd;
      sys.b_d[index] = b_d;
      ++index;
    }
  };
  concurrency::runTasks(tasks_, n, linearizeHost);
  double residual_energy = 0.0;
  for (const HostTerms& ht : host_terms_) {
    for (size_t i = 0; i < ht.energies.size(); ++i) {
      const float e = ht.energies[i];
      residual_energy += e;
      if (ht.inlier[i] != 0) {
        sys.inlier_energy += e;
        ++sys.inliers;
      }
    }
    sys.outliers += ht.outliers;
  }
  addPairAccumulators(n, pair_acc_, pairs_, adjoints_, sys.H, sys.b);
  sys.photometric_energy = 0.5 * residual_energy;
  sys.energy = sys.photometric_energy + addPriors(window, prior, &sys.H, &sys.b);
}

void WindowOptimizer::linearizeCalibration(const std::vector<WindowKeyframe*>& window,
                                           System& sys) {
  const int n = static_cast<int>(window.size());
  sys.calibration.reset(sys.H.rows());
  calibration_pair_.assign(static_cast<size_t>(n) * n, RelCalibMatrix::Zero());
  CalibrationResidualTerms rt;
  rt.params = settings_.estimate_calibration;
  const std::vector<int> refined = refinedParams(rt.params);
  const int dim = kFrameParams * n;
  EliminatedDepthTerms& other = sys.calibration.other_depths;
  Eigen::VectorXd c(dim);
  std::vector<char> touched(static_cast<size_t>(n));
  for (int h = 0; h < n; ++h)
    for (auto& pt : window[h]->points) {
      // A fixed point has no coupling column: its frame coupling is made here, with its
      // calibration terms, and its depth eliminated into sys.calibration.other_depths.
      const bool fixed = pt->fixed;
      if (fixed) {
        c.setZero();
        std::fill(touched.begin(), touched.end(), 0);
        touched[static_cast<size_t>(h)] = 1;
      }
      CalibVector H_dc = CalibVector::Zero();
      double H_dd = 0.0, b_d = 0.0;
      const Eigen::Vector2f host = hostPixel(*pt);
      for (auto& res : pt->residuals) {
        const int t = res.target->window_index;
        const size_t pi = static_cast<size_t>(h) * n + t;
        ResidualAccumulator acc;
        acc.calibration = &rt;
        acc.calibration_only = !fixed;
        acc.pair = &pair_acc_[pi];  // (a fixed point's pair sums: discarded)
        evaluateResidual(*pt, host, res, pairs_[pi], settings_.residual, &acc);
        if (res.state != ResidualState::Inlier) continue;
        calibration_pair_[pi] += rt.coupling;
        sys.calibration.H_cc += rt.H_cc;
        sys.calibration.b_c += rt.b_c;
        H_dc += rt.H_dc;
        if (fixed) {
          addCoupling(adjoints_[pi], acc.coupling, h, t, c);
          touched[static_cast<size_t>(t)] = 1;
          H_dd += acc.H_dd;
          b_d += acc.b_d;
        }
      }
      if (!fixed) {
        sys.calibration.H_dc.push_back(H_dc);
        continue;
      }
      if (!(H_dd > 1e-10)) continue;
      const double d = 1.0 / H_dd;
      // c is non-zero only in the host's and the inlier targets' blocks: only their products
      // (the lower ones; mirrored below).
      constexpr int k = kFrameParams;
      forTouchedLowerBlocks(touched, [&](int i, int j) {
        other.A.block<k, k>(k * i, k * j).noalias() +=
            c.segment<k>(k * i) * (c.segment<k>(k * j).transpose() * d);
      });
      other.g += c * (b_d * d);
      for (int p : refined) other.h.col(p) += c * (H_dc[p] * d);
      for (int p : refined) {
        other.bc[p] += H_dc[p] * (b_d * d);
        for (int q : refined) other.hcc(p, q) += H_dc[p] * (H_dc[q] * d);
      }
    }
  other.A.triangularView<Eigen::StrictlyUpper>() = other.A.transpose();
  for (size_t pi = 0; pi < calibration_pair_.size(); ++pi) {
    const int h = static_cast<int>(pi) / n, t = static_cast<int>(pi) % n;
    if (h == t) continue;
    for (int p : refined)
      addCoupling(adjoints_[pi], calibration_pair_[pi].col(p), h, t, sys.calibration.H_fc.col(p));
  }
}

void WindowOptimizer::solve(const System& sys, double lambda, Eigen::VectorXd& frame_step,
                            std::vector<double>& point_step) const {
  const Eigen::Index dim = sys.H.rows();
  const size_t np = sys.points.size();
  // Per coupling column (the points whose depths move; a fixed point takes no step and adds no
  // Schur term).
  Eigen::VectorXd inv_dd(sys.num_points);
  for (size_t i = 0; i < np; ++i) {
    const Eigen::Index c = sys.column[i];
    if (c < 0) continue;
    const double hdd = sys.H_dd[i] * (1.0 + lambda);
    inv_dd[c] = hdd > 1e-10 ? 1.0 / hdd : 0.0;
  }
  Eigen::MatrixXd Hs = sys.H;
  const auto coupling = sys.coupling();
  subtractDepthSchur(Hs, coupling, inv_dd, schur_scratch_);
  Eigen::VectorXd bs = sys.b;
  for (size_t i = 0; i < np; ++i) {
    const Eigen::Index c = sys.column[i];
    if (c >= 0) bs -= coupling.col(c) * (sys.b_d[i] * inv_dd[c]);
  }

  // Jacobi scaling makes poses, affine parameters and depths comparable; LM damping on top.
  Eigen::VectorXd s(dim);
  for (Eigen::Index i = 0; i < dim; ++i) s[i] = 1.0 / std::sqrt(std::max(Hs(i, i), 1e-12));
  Eigen::MatrixXd A = s.asDiagonal() * Hs * s.asDiagonal();
  A.diagonal().array() += lambda + 1e-10;
  const Eigen::VectorXd y = A.ldlt().solve(-(s.asDiagonal() * bs));
  frame_step = s.asDiagonal() * y;
  if (!frame_step.allFinite()) frame_step.setZero(dim);

  point_step.assign(np, 0.0);
  for (size_t i = 0; i < np; ++i) {
    const Eigen::Index c = sys.column[i];
    if (c >= 0) point_step[i] = -(sys.b_d[i] + coupling.col(c).dot(frame_step)) * inv_dd[c];
  }
}

void WindowOptimizer::saveResidualStates(const std::vector<ActivePoint*>& points) {
  saved_points_.clear();
  saved_residuals_.clear();
  for (const ActivePoint* p : points) {
    saved_points_.push_back({p->hessian_idepth, p->gradient_idepth, p->inlier_residuals});
    saved_residuals_.insert(saved_residuals_.end(), p->residuals.begin(), p->residuals.end());
  }
}

void WindowOptimizer::restoreResidualStates(const std::vector<ActivePoint*>& points) {
  std::size_t r = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    ActivePoint& p = *points[i];
    p.hessian_idepth = saved_points_[i].hessian_idepth;
    p.gradient_idepth = saved_points_[i].gradient_idepth;
    p.inlier_residuals = saved_points_[i].inlier_residuals;
    for (PointResidual& res : p.residuals) res = saved_residuals_[r++];
  }
}

double WindowOptimizer::evaluate(const std::vector<WindowKeyframe*>& window,
                                 const MarginalizationPrior& prior) {
  precalcPairs(window);
  const int n = static_cast<int>(window.size());
  double e = 0.0;
  for (int h = 0; h < n; ++h)
    for (auto& pt : window[h]->points) {
      int inl = 0;
      const Eigen::Vector2f host = hostPixel(*pt);
      for (auto& res : pt->residuals) {
        const size_t pi = static_cast<size_t>(h) * n + res.target->window_index;
        const float r = evaluateResidual(*pt, host, res, pairs_[pi], settings_.residual, nullptr);
        const bool inlier = res.state == ResidualState::Inlier;
        e += inlier ? r : outlierEnergy(pairs_[pi], settings_.residual);
        inl += inlier ? 1 : 0;
      }
      pt->inlier_residuals = inl;
    }
  return 0.5 * e + addPriors(window, prior, nullptr, nullptr);
}

WindowOptimizationResult WindowOptimizer::optimize(const std::vector<WindowKeyframe*>& window,
                                                   const MarginalizationPrior& prior) {
  WindowOptimizationResult result;
  if (window.size() < 2) return result;
  System& sys = sys_;
  System& trial = trial_;
  precalcPairs(window);
  linearize(window, prior, sys);
  result.initial_energy = sys.energy;
  double lambda = settings_.initial_lambda;
  Eigen::VectorXd frame_step;
  std::vector<double> point_step;
  for (int it = 0; it < settings_.max_iterations; ++it) {
    solve(sys, lambda, frame_step, point_step);
    for (size_t i = 0; i < window.size(); ++i) {
      window[i]->backup();
      window[i]->applyStep(frame_step.segment<kFrameParams>(kFrameParams * i));
    }
    for (size_t i = 0; i < sys.points.size(); ++i) {
      ActivePoint& p = *sys.points[i];
      p.idepth_backup = p.idepth;
      const double nd = p.idepth + point_step[i];
      // Keep depths positive: a point cannot jump behind its host.
      p.idepth = std::max(static_cast<float>(nd > 0.25 * p.idepth ? nd : 0.25 * p.idepth),
                          kMinInverseDepth);
    }
    saveResidualStates(sys.points);
    precalcPairs(window);
    linearize(window, prior, trial);
    ++result.iterations;
    // Relative to the residuals' energy: the marginalisation prior's has no constant term and
    // is often negative and larger (kitti00_200: -1.7e6 against 1.6e6), and relative to the sum
    // a step's change said nothing (the sum near 0 or below it: no step ever looked converged).
    const double change = (sys.energy - trial.energy) / std::max(sys.photometric_energy, 1e-12);
    if (trial.energy <= sys.energy) {
      std::swap(sys, trial);
      lambda = std::max(lambda * 0.5, 1e-8);
      if (change < settings_.min_relative_decrease) break;
    } else {
      for (auto* kf : window) kf->restore();
      for (auto* p : sys.points) p->idepth = p->idepth_backup;
      lambda *= 8.0;
      precalcPairs(window);
      restoreResidualStates(sys.points);  // as the kept state's linearisation left them
      // A step that raises the energy a little is at the noise floor of the residuals (outliers
      // flipping, points at the edge of the view): converged. Only an overshoot is retried with
      // more damping: on kitti00_200 every rejected step raised the energy by less than 1e-3 of
      // the residuals' and no retry of one was ever accepted (87 of 573 trial linearisations),
      // while a window far from its optimum (after a gap in the images) needs them.
      if (-change < settings_.retry_increase || lambda > 1e4) break;
    }
  }
  result.final_energy = sys.energy;
  result.inlier_residuals = sys.inliers;
  result.outlier_residuals = sys.outliers;
  result.rmse = sys.inliers > 0 ? std::sqrt(sys.inlier_energy / (sys.inliers * kPatternSize)) : 0.0;
  const CalibMask& mask = settings_.estimate_calibration;
  if (!refinedParams(mask).empty()) {
    linearizeCalibration(window, sys);
    // The envelope is taken over this window's own information: the marginalisation prior
    // holds the poses where residuals evaluated with the camera of their time put them, and it
    // has no calibration columns, so with it every change of the camera looks expensive and
    // the estimate stops short (a focal length told 5 % short: a quarter of the error found with
    // it, all of it without; docs/engine.md). The windows' estimates are fused over keyframes
    // instead (CalibrationRefinement).
    Eigen::MatrixXd H = sys.H;
    Eigen::VectorXd b = sys.b;
    addMarginalizationPrior(window, prior, -1.0, &H, &b);
    std::vector<double> H_dd, b_d;  // per coupling column
    H_dd.reserve(static_cast<size_t>(sys.num_points));
    b_d.reserve(static_cast<size_t>(sys.num_points));
    for (size_t i = 0; i < sys.points.size(); ++i)
      if (sys.column[i] >= 0) {
        H_dd.push_back(sys.H_dd[i]);
        b_d.push_back(sys.b_d[i]);
      }
    result.calibration_valid = calibrationEnvelopeStep(
        H, b, sys.coupling(), H_dd, b_d, sys.calibration, mask, &result.calibration_step,
        &result.calibration_curvature, &schur_scratch_);
  }
  return result;
}

CalibVector WindowOptimizer::calibrationGradient(const std::vector<WindowKeyframe*>& window,
                                                 const MarginalizationPrior& prior) {
  System sys;
  precalcPairs(window);
  linearize(window, prior, sys);
  linearizeCalibration(window, sys);
  return sys.calibration.b_c;
}

Eigen::VectorXd WindowOptimizer::frameGradient(const std::vector<WindowKeyframe*>& window,
                                               const MarginalizationPrior& prior) {
  System sys;
  precalcPairs(window);
  linearize(window, prior, sys);
  return sys.b;
}

void WindowOptimizer::marginalizePoints(const std::vector<WindowKeyframe*>& window,
                                        const std::vector<const ActivePoint*>& points,
                                        MarginalizationPrior& prior) {
  if (points.empty()) return;
  precalcPairs(window);
  const int n = static_cast<int>(window.size());
  const int dim = kFrameParams * n;
  resetPairAccumulators(static_cast<size_t>(n) * n, pair_acc_);
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(dim, dim);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(dim);
  Eigen::VectorXd c(dim);
  // A point's coupling c is non-zero only in its host's and its inlier targets' blocks, so its
  // term c c^T / H_dd touches only those blocks' products, and only the lower ones are formed
  // (c_i c_j = c_j c_i exactly: the upper triangle is mirrored once at the end). Each element
  // gets the same operations, in the same order, as the dense outer product of every column.
  std::vector<char> touched(static_cast<size_t>(n));
  for (const ActivePoint* point : points) {
    if (point->fixed) continue;  // the map's points never enter the prior
    const int h = point->host->window_index;
    c.setZero();
    std::fill(touched.begin(), touched.end(), 0);
    touched[static_cast<size_t>(h)] = 1;
    double H_dd = 0.0, b_d = 0.0;
    // The evaluation updates residual states: copies, the point's own stay as they are.
    residual_scratch_.assign(point->residuals.begin(), point->residuals.end());
    const Eigen::Vector2f host = hostPixel(*point);
    for (PointResidual& res : residual_scratch_) {
      const int t = res.target->window_index;
      const size_t pi = static_cast<size_t>(h) * n + t;
      ResidualAccumulator acc;
      acc.pair = &pair_acc_[pi];
      evaluateResidual(*point, host, res, pairs_[pi], settings_.residual, &acc);
      if (res.state != ResidualState::Inlier) continue;
      addCoupling(adjoints_[pi], acc.coupling, h, t, c);
      touched[static_cast<size_t>(t)] = 1;
      H_dd += acc.H_dd;
      b_d += acc.b_d;
    }
    if (H_dd < 1e-10) continue;
    constexpr int k = kFrameParams;
    forTouchedLowerBlocks(touched, [&](int i, int j) {
      H.block<k, k>(k * i, k * j).noalias() -=
          c.segment<k>(k * i) * c.segment<k>(k * j).transpose() / H_dd;
    });
    b -= c * (b_d / H_dd);
  }
  H.triangularView<Eigen::StrictlyUpper>() = H.transpose();
  addPairAccumulators(n, pair_acc_, pairs_, adjoints_, H, b);
  prior.add(windowIds(window), H, b, stackedDeltas(window));
}

void WindowOptimizer::marginalizeFrame(const std::vector<WindowKeyframe*>& window,
                                       const WindowKeyframe& frame, MarginalizationPrior& prior) {
  // The frame's own priors go into the marginalisation prior before it is eliminated.
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(kFrameParams, kFrameParams);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(kFrameParams);
  H(6, 6) = settings_.affine_prior_a;
  H(7, 7) = settings_.affine_prior_b;
  b[6] = settings_.affine_prior_a * frame.aff.a;
  b[7] = settings_.affine_prior_b * frame.aff.b;
  const double anchor = frame.is_gauge_anchor ? settings_.gauge_anchor_weight : frame.anchor_weight;
  if (anchor > 0.0) {
    const FrameVector w = anchorWeights(frame, anchor);
    H.diagonal() += w;
    b += w.cwiseProduct(frame.delta());
  }
  prior.add({frame.id()}, H, b, frame.delta());
  for (const auto* kf : window) prior.ensureFrame(kf->id());
  prior.marginalizeFrame(frame.id());
}

}  // namespace ldsm
