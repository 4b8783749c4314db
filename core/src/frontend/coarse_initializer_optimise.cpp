// The coarse initializer's optimisation: energy and normal equations of one level (with the
// depths' Schur data per point), the Levenberg-Marquardt loop, the scale gauge and the depth
// propagation between levels.
//
// Residual of pattern pixel k of a reference point (pixel u_k at its level, inverse depth d):
//   q_k = R r_k + t d   (r_k = K^-1 u_k: the host point scaled by d, so d = 0 is valid),
//   r_k = I_frame[pi(q_k)] - (s I_ref[u_k] + b),   s = exp(a) e_frame / e_ref.
// Parameters x = [rho, phi, a, b] with T <- exp([rho, phi]) T. The geometric Jacobian of the
// pattern is taken at the point's centre (as DSO does), so a point's 8 residuals reduce to a few
// sums before they touch the 8x8 system.
#include <algorithm>
#include <cmath>

#include "frontend/coarse_initializer.h"
#include "image/interpolation.h"

namespace ldsm {

namespace {

using Mat88f = Eigen::Matrix<float, 8, 8>;
using Vec8f = Eigen::Matrix<float, 8, 1>;

/// Points per float block before it is added into the double sums.
constexpr int kFlushEvery = 64;
/// Points closer to the camera plane than this (in units of q = d * P) are not evaluated.
constexpr float kMinDepth = 1e-3f;

float huberCost(float r, float k) {
  const float a = std::abs(r);
  return a <= k ? 0.5f * r * r : k * (a - 0.5f * k);
}

/// What one point's pattern contributes: its energy and the weighted sums its 8 residuals reduce
/// to (image-gradient moments with the residual and the affine derivatives).
struct PatternSums {
  bool ok = false;  ///< every pattern pixel in front of the camera and inside the image
  float e = 0.f;    ///< weighted Huber energy
  float a00 = 0, a01 = 0, a11 = 0, b0 = 0, b1 = 0, ca0 = 0, ca1 = 0, cb0 = 0, cb1 = 0;
  float saa = 0, sab = 0, sbb = 0, sar = 0, sbr = 0;
};

/// The photometric terms shared by all points of a level.
struct PatternModel {
  const Eigen::Vector3f* dq;  ///< pattern offsets rotated into the frame
  ImageView<const GradientPixel> img;
  float fx, fy, cx, cy;
  float scale, offset, huber, c2;
};

inline PatternSums patternSums(const PatternModel& m, const Eigen::Vector3f& qc,
                               const float* ref_colors) {
  PatternSums s;
  s.ok = qc.z() > kMinDepth;
  for (int k = 0; s.ok && k < kPatternSize; ++k) {
    const Eigen::Vector3f q = qc + m.dq[k];
    if (!(q.z() > kMinDepth)) {
      s.ok = false;
      break;
    }
    const float iz = 1.f / q.z();
    const float x = m.fx * q.x() * iz + m.cx;
    const float y = m.fy * q.y() * iz + m.cy;
    if (!isInsideForBilinear(x, y, m.img.width, m.img.height, 1.f)) {
      s.ok = false;
      break;
    }
    const GradientPixel g = interpolateBilinear(m.img, x, y);
    const float ref = ref_colors[k];
    const float res = g.intensity - (m.scale * ref + m.offset);
    const float wg = m.c2 > 0.f ? m.c2 / (m.c2 + g.dx * g.dx + g.dy * g.dy) : 1.f;
    const float ares = std::abs(res);
    const float hw = ares <= m.huber ? 1.f : m.huber / ares;
    s.e += wg * huberCost(res, m.huber);
    const float w = wg * hw;
    const float ja = -m.scale * ref;  // dr/da; dr/db = -1
    const float wgx = w * g.dx, wgy = w * g.dy;
    s.a00 += wgx * g.dx;
    s.a01 += wgx * g.dy;
    s.a11 += wgy * g.dy;
    s.b0 += wgx * res;
    s.b1 += wgy * res;
    s.ca0 += wgx * ja;
    s.ca1 += wgy * ja;
    s.cb0 -= wgx;
    s.cb1 -= wgy;
    s.saa += w * ja * ja;
    s.sab -= w * ja;
    s.sbb += w;
    s.sar += w * ja * res;
    s.sbr -= w * res;
  }
  return s;
}

/// An inlier's linearisation: its pose and affine blocks go into the float sums Hf, bf (added
/// into the double sums by the caller every kFlushEvery points), its own row and depth terms into
/// P, and its squared translation flow (level-0 pixels) into `flow_sq_sum`. `qc`: the centre
/// projected with the current pose, `d` its inverse depth. (`Linearization`:
/// CoarseInitializer::PointLinearization.)
template <typename Linearization>
void linearizeInlier(const PatternSums& ps, const Eigen::Vector3f& qc, float d,
                     const Eigen::Vector3f& t, float fx, float fy, float to_level0, Mat88f& Hf,
                     Vec8f& bf, Linearization& P, double& flow_sq_sum) {
  // Centre geometry: normalised coordinates, 1/z of q and the Jacobians of pi.
  const float iz = 1.f / qc.z();
  const float nx = qc.x() * iz, ny = qc.y() * iz;
  const float dz = d * iz;  // 1 / depth of the point in the frame
  Eigen::Matrix<float, 2, 6> G;
  G << fx * dz, 0.f, -fx * nx * dz, -fx * nx * ny, fx * (1.f + nx * nx), -fx * ny,  //
      0.f, fy * dz, -fy * ny * dz, -fy * (1.f + ny * ny), fy * nx * ny, fy * nx;
  const Eigen::Vector2f v(fx * iz * (t.x() - nx * t.z()), fy * iz * (t.y() - ny * t.z()));
  Eigen::Matrix2f A;
  A << ps.a00, ps.a01, ps.a01, ps.a11;
  const Eigen::Vector2f B(ps.b0, ps.b1);
  const Eigen::Vector2f Ca(ps.ca0, ps.ca1);
  const Eigen::Vector2f Cb(ps.cb0, ps.cb1);

  const Eigen::Matrix<float, 2, 6> AG = A * G;
  Hf.topLeftCorner<6, 6>().noalias() += G.transpose() * AG;
  Hf.block<6, 1>(0, 6).noalias() += G.transpose() * Ca;
  Hf.block<6, 1>(0, 7).noalias() += G.transpose() * Cb;
  Hf(6, 6) += ps.saa;
  Hf(6, 7) += ps.sab;
  Hf(7, 7) += ps.sbb;
  bf.head<6>().noalias() += G.transpose() * B;
  bf(6) += ps.sar;
  bf(7) += ps.sbr;

  const Eigen::Vector2f Av = A * v;
  P.hphoto = v.dot(Av);
  P.hdd += P.hphoto;
  P.bd += v.dot(B);
  P.hxd.template head<6>().noalias() = G.transpose() * Av;
  P.hxd(6) = Ca.dot(v);
  P.hxd(7) = Cb.dot(v);

  // Flow due to translation: pi(q) against pi(q - t d), in level-0 pixels.
  const Eigen::Vector3f qr = qc - t * d;
  if (qr.z() > kMinDepth) {
    const float izr = 1.f / qr.z();
    const float fu = fx * (nx - qr.x() * izr) * to_level0;
    const float fv = fy * (ny - qr.y() * izr) * to_level0;
    flow_sq_sum += fu * fu + fv * fv;
  }
}

}  // namespace

void CoarseInitializer::evaluate(int lvl, const SE3d& T, const AffineLight& affine,
                                 const float* idepth, const float* ir, PointLinearization* lin,
                                 std::uint8_t* good, Evaluation& out) const {
  const Level& L = levels_data_[lvl];
  const LevelCamera& cam = camera_[lvl];
  const ImageView<const GradientPixel> img = frame_->gradients(lvl);
  const Eigen::Matrix3f R = T.rotationMatrix().cast<float>();
  const Eigen::Vector3f t = T.translation().cast<float>();
  Eigen::Vector3f dq[kPatternSize];
  for (int k = 0; k < kPatternSize; ++k) {
    dq[k] = R.col(0) * (static_cast<float>(kPatternOffsets[k][0]) * cam.fxi) +
            R.col(1) * (static_cast<float>(kPatternOffsets[k][1]) * cam.fyi);
  }
  const float scale = static_cast<float>(std::exp(affine.a)) * exposure_ratio_;
  const float offset = static_cast<float>(affine.b);
  const float huber = settings_.huber_threshold;
  const float c2 = settings_.gradient_weight_c * settings_.gradient_weight_c;
  const float cap = kPatternSize * huberCost(settings_.outlier_rms, huber);
  const float ws = smoothness_weight_;
  const float wp = settings_.idepth_prior_weight;
  const float to_level0 = static_cast<float>(1 << lvl);
  const float fx = cam.fx, fy = cam.fy;
  const PatternModel model{dq, img, fx, fy, cam.cx, cam.cy, scale, offset, huber, c2};

  out.H.setZero();
  out.b.setZero();
  out.energy = out.photo_good = out.photo_all = out.flow_sq_sum = 0;
  out.good = 0;
  out.finite = true;
  Mat88f Hf = Mat88f::Zero();
  Vec8f bf = Vec8f::Zero();
  int in_block = 0;
  double reg_energy = 0;

  const int n = static_cast<int>(L.u.size());
  for (int i = 0; i < n; ++i) {
    const float d = idepth[i];
    const float dr = d - ir[i];
    const float dp = d - 1.f;
    reg_energy += 0.5f * (ws * dr * dr + wp * dp * dp);
    PointLinearization& P = lin[i];
    P.hxd.setZero();
    P.hdd = ws + wp;
    P.bd = ws * dr + wp * dp;
    P.hphoto = 0.f;
    P.energy = cap;
    good[i] = 0;

    const Eigen::Vector3f qc = R * cam.unproject(L.u[i].x(), L.u[i].y()) + t * d;
    const PatternSums ps = patternSums(model, qc, L.ref[i].data());
    const bool ok = ps.ok;
    const float e = ps.e;
    if (ok && !std::isfinite(e)) out.finite = false;
    if (!ok || !(e <= cap)) {
      out.energy += cap;
      out.photo_all += cap;
      continue;
    }
    out.energy += e;
    out.photo_good += e;
    out.photo_all += e;
    ++out.good;
    good[i] = 1;
    P.energy = e;

    linearizeInlier(ps, qc, d, t, fx, fy, to_level0, Hf, bf, P, out.flow_sq_sum);

    if (++in_block == kFlushEvery) {
      out.H += Hf.cast<double>();
      out.b += bf.cast<double>();
      Hf.setZero();
      bf.setZero();
      in_block = 0;
    }
  }
  out.H += Hf.cast<double>();
  out.b += bf.cast<double>();
  addPriors(affine, n, reg_energy, out);
}

void CoarseInitializer::addPriors(const AffineLight& affine, int n, double reg_energy,
                                  Evaluation& out) const {
  for (int r = 1; r < 8; ++r) {
    for (int c = 0; c < r; ++c) out.H(r, c) = out.H(c, r);
  }
  // Affine prior, scaled with the number of points so that its strength relative to the data
  // is the same on every level.
  const double wa = settings_.affine_prior_weight_a * static_cast<double>(n);
  const double wb = settings_.affine_prior_weight_b * static_cast<double>(n);
  out.H(6, 6) += wa;
  out.H(7, 7) += wb;
  out.b(6) += wa * affine.a;
  out.b(7) += wb * affine.b;
  out.energy += reg_energy + 0.5 * (wa * affine.a * affine.a + wb * affine.b * affine.b);
  out.finite = out.finite && std::isfinite(out.energy) && out.H.allFinite() && out.b.allFinite();
}

bool CoarseInitializer::computeStep(int lvl, double lambda, SE3d& T_new, AffineLight& affine_new) {
  Level& L = levels_data_[lvl];
  Eigen::Matrix<double, 8, 8> H = eval_.H;
  Eigen::Matrix<double, 8, 1> b = eval_.b;
  H.diagonal() *= 1.0 + lambda;
  const float damp = static_cast<float>(1.0 + lambda);
  // Schur complement of the depths, accumulated in float blocks.
  Mat88f Hs = Mat88f::Zero();
  Vec8f bs = Vec8f::Zero();
  const std::size_t n = L.u.size();
  for (std::size_t i = 0; i < n; ++i) {
    const PointLinearization& P = L.lin[i];
    const float inv = 1.f / (P.hdd * damp);
    const Vec8f s = P.hxd * inv;
    Hs.noalias() += s * P.hxd.transpose();
    bs.noalias() += s * P.bd;
    if ((i + 1) % kFlushEvery == 0) {
      H -= Hs.cast<double>();
      b -= bs.cast<double>();
      Hs.setZero();
      bs.setZero();
    }
  }
  H -= Hs.cast<double>();
  b -= bs.cast<double>();

  // Jacobi scaling for conditioning, then a tiny absolute damping.
  Eigen::Matrix<double, 8, 1> s;
  for (int j = 0; j < 8; ++j) s(j) = 1.0 / std::sqrt(std::max(H(j, j), 1e-12));
  Eigen::Matrix<double, 8, 8> Hn = s.asDiagonal() * H * s.asDiagonal();
  Hn.diagonal().array() += 1e-9;
  const Eigen::Matrix<double, 8, 1> step = -(s.asDiagonal() * Hn.ldlt().solve(s.cwiseProduct(b)));
  if (!step.allFinite()) return false;

  T_new = SE3d::exp(step.head<6>()) * T_;
  affine_new.a = affine_.a + step(6);
  affine_new.b = affine_.b + step(7);
  const Vec8f stepf = step.cast<float>();
  for (std::size_t i = 0; i < n; ++i) {
    const PointLinearization& P = L.lin[i];
    L.idepth_trial[i] = L.idepth[i] - (P.bd + P.hxd.dot(stepf)) / (P.hdd * damp);
  }
  return true;
}

int CoarseInitializer::optimiseLevel(int lvl) {
  Level& L = levels_data_[lvl];
  computeSmoothnessTargets(lvl, L.idepth.data(), L.ir.data());
  evaluate(lvl, T_, affine_, L.idepth.data(), L.ir.data(), L.lin.data(), L.good.data(), eval_);
  double lambda = settings_.initial_lambda;
  int iterations = 0;
  SE3d T_new;
  AffineLight affine_new;
  for (int it = 0; it < settings_.max_iterations[lvl]; ++it) {
    ++iterations;
    if (!computeStep(lvl, lambda, T_new, affine_new)) break;
    computeSmoothnessTargets(lvl, L.idepth_trial.data(), L.ir_trial.data());
    evaluate(lvl, T_new, affine_new, L.idepth_trial.data(), L.ir_trial.data(), L.lin_trial.data(),
             L.good_trial.data(), eval_trial_);
    if (eval_trial_.finite && eval_trial_.energy < eval_.energy) {
      const double decrease = (eval_.energy - eval_trial_.energy) / eval_.energy;
      std::swap(L.idepth, L.idepth_trial);
      std::swap(L.ir, L.ir_trial);
      std::swap(L.lin, L.lin_trial);
      std::swap(L.good, L.good_trial);
      std::swap(eval_, eval_trial_);
      T_ = T_new;
      affine_ = affine_new;
      lambda = std::max(lambda * 0.5, 1e-6);
      if (decrease < settings_.convergence_energy_fraction) break;
    } else {
      lambda *= 4.0;
      if (lambda > 1e6) break;
    }
  }
  return iterations;
}

void CoarseInitializer::normaliseScale(int lvl) {
  const Level& L = levels_data_[lvl];
  double sum = 0;
  for (const float d : L.idepth) sum += d;
  const double mean = L.idepth.empty() ? 0.0 : sum / static_cast<double>(L.idepth.size());
  if (!(mean > 1e-6) || !std::isfinite(mean)) return;  // degenerate: leave it to decide()
  const float inv = static_cast<float>(1.0 / mean);
  const float h_scale = static_cast<float>(mean * mean);
  for (int l = 0; l < levels_; ++l) {
    Level& M = levels_data_[l];
    for (std::size_t i = 0; i < M.idepth.size(); ++i) {
      M.idepth[i] *= inv;
      M.ir[i] *= inv;
      M.lin[i].hphoto *= h_scale;
    }
  }
  T_.translation() *= mean;
}

void CoarseInitializer::computeSmoothnessTargets(int lvl, const float* idepth, float* ir) const {
  const Level& L = levels_data_[lvl];
  if (smoothness_weight_ == 0.f) return;  // unused
  float values[CoarseInitializerSettings::kMaxNeighbours];
  for (std::size_t i = 0; i < L.u.size(); ++i) {
    const int m = L.neighbour_count[i];
    if (m == 0) {
      ir[i] = idepth[i];
      continue;
    }
    for (int j = 0; j < m; ++j) values[j] = idepth[L.neighbours[i][j]];
    std::nth_element(values, values + m / 2, values + m);
    ir[i] = values[m / 2];
  }
}

void CoarseInitializer::propagateDown(int lvl) {
  Level& L = levels_data_[lvl];
  const Level& P = levels_data_[lvl + 1];
  for (std::size_t i = 0; i < L.u.size(); ++i) {
    const int p = L.parent[i];
    if (p < 0 || !P.good[static_cast<std::size_t>(p)]) continue;
    const float hp = P.lin[static_cast<std::size_t>(p)].hphoto;
    if (!(hp > 0.f)) continue;
    const float hc = L.good[i] ? 2.f * L.lin[i].hphoto : 0.f;
    L.idepth[i] = (hc * L.idepth[i] + hp * P.idepth[static_cast<std::size_t>(p)]) / (hc + hp);
  }
}

void CoarseInitializer::propagateUp() {
  for (int lvl = 0; lvl + 1 < levels_; ++lvl) {
    const Level& L = levels_data_[lvl];
    Level& P = levels_data_[lvl + 1];
    std::fill(P.accum_w.begin(), P.accum_w.end(), 0.f);
    std::fill(P.accum_wd.begin(), P.accum_wd.end(), 0.f);
    for (std::size_t i = 0; i < L.u.size(); ++i) {
      const int p = L.parent[i];
      const float h = L.lin[i].hphoto;
      if (p < 0 || !L.good[i] || !(h > 0.f)) continue;
      P.accum_w[static_cast<std::size_t>(p)] += h;
      P.accum_wd[static_cast<std::size_t>(p)] += h * L.idepth[i];
    }
    for (std::size_t j = 0; j < P.u.size(); ++j) {
      if (P.accum_w[j] > 0.f) P.idepth[j] = P.accum_wd[j] / P.accum_w[j];
    }
  }
}

}  // namespace ldsm
