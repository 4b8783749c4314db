#include "backend/photometric_residual.h"

#include <algorithm>
#include <cmath>

#include "image/interpolation.h"

namespace ldsm {

void FramePairPrecalc::set(const WindowKeyframe& host, const WindowKeyframe& target,
                           const LevelCamera& camera) {
  cam = camera;
  const SE3d T_th = target.T_c_w * host.T_c_w.inverse();
  const SE3d T_th0 = target.T_c_w_eval * host.T_c_w_eval.inverse();
  const Eigen::Matrix3f K = camera.K();
  Eigen::Matrix3f Ki;
  Ki << camera.fxi, 0, camera.cxi, 0, camera.fyi, camera.cyi, 0, 0, 1;
  KRKi = K * T_th.rotationMatrix().cast<float>() * Ki;
  Kt = K * T_th.translation().cast<float>();
  R0 = T_th0.rotationMatrix().cast<float>();
  t0 = T_th0.translation().cast<float>();
  const Eigen::Vector2d st =
      affineTransfer(host.exposure(), target.exposure(), host.aff, target.aff);
  scale = static_cast<float>(st[0]);
  offset = static_cast<float>(st[1]);
  host_b = static_cast<float>(host.aff.b);
  outlier_energy = std::max(host.outlier_energy, target.outlier_energy);
  target_image = target.pyramid().level0();

  std::copy(KRKi.data(), KRKi.data() + 9, sampling.KRKi);
  std::copy(Kt.data(), Kt.data() + 3, sampling.Kt);
  sampling.scale = scale;
  sampling.offset = offset;
  sampling.image = target_image.full;
  sampling.intensity = target_image.intensity;
  sampling.compact = target_image.compact;
}

void PairAccumulator::reduce(const FramePairPrecalc& pair, RelMatrix& H, RelVector& b) const {
  double t[simd::kPatternPairSums];
  sums_.totals(t);
  // Relative parameter a is factor[a] times basis row basis[a] (u = [eps (6), a_h, 1]):
  // b_h = scale * 1, a_t = -a_h, b_t = -1.
  constexpr int basis[kRelParams] = {0, 1, 2, 3, 4, 5, 6, 7, 6, 7};
  const double s = pair.scale;
  const double factor[kRelParams] = {1, 1, 1, 1, 1, 1, 1, s, -1, -1};
  for (int a = 0; a < kRelParams; ++a) {
    b[a] = factor[a] * t[simd::patternGradientIndex(basis[a])];
    for (int c = a; c < kRelParams; ++c) {
      const int i = std::min(basis[a], basis[c]), j = std::max(basis[a], basis[c]);
      H(a, c) = H(c, a) = factor[a] * factor[c] * t[simd::patternUpperIndex(i, j)];
    }
  }
}

Eigen::Vector2f hostRayPixel(const LevelCamera& cam, float k, float u, float v) {
  if (k == 0.f) return {u, v};
  const Eigen::Vector2f x = removeRadial(k, cam.fxi * u + cam.cxi, cam.fyi * v + cam.cyi);
  return {cam.fx * x.x() + cam.cx, cam.fy * x.y() + cam.cy};
}

namespace {

/// d(image normalized) / d(pinhole normalized) at x: (1 + k r^2) I + 2 k x x^T.
Eigen::Matrix2f radialJacobian(float k, float x, float y) {
  const float f = 1.f + k * (x * x + y * y);
  Eigen::Matrix2f J;
  J << f + 2.f * k * x * x, 2.f * k * x * y, 2.f * k * x * y, f + 2.f * k * y * y;
  return J;
}

/// The same in pixels: K J_D K^-1 (a pinhole pixel's displacement to the image's).
Eigen::Matrix2f pixelRadialJacobian(const LevelCamera& cam, float k, float x, float y) {
  Eigen::Matrix2f J = radialJacobian(k, x, y);
  J(0, 1) *= cam.fx * cam.fyi;
  J(1, 0) *= cam.fy * cam.fxi;
  return J;
}

using CalibJacobian = Eigen::Matrix<float, 2, kCalibParams>;

/// d(pixel) / d(eps) and d(pixel) / d(inverse depth) of the point's centre at the linearisation
/// point (first estimates), for the host ray through pinhole pixel (u, v).
/// With `dpx_dc`, also d(pixel) / d(calibration correction c) at the pair's camera (the columns
/// of `params`; the others 0): the host ray's move through the projection (the host pixel stays,
/// its ray turns) plus the change of the target's projection itself. With `depth_only`, only
/// d(pixel) / d(inverse depth), by the same operations (dpx_dc must be null).
void centreJacobian(float u, float v, float d, const FramePairPrecalc& pair,
                    simd::PatternJacobian& jac, CalibJacobian* dpx_dc, const CalibMask& params,
                    bool depth_only = false) {
  const LevelCamera& cam = pair.cam;
  const Eigen::Vector3f ray = cam.unproject(u, v);
  const Eigen::Vector3f R_ray = pair.R0 * ray;
  const Eigen::Vector3f p = R_ray / d + pair.t0;  // point in the target, metric
  const float zi = 1.f / p.z();
  // dpx/dp * dp/dd with dp/dd = -(p - t0) / d, in the form without cancellation: with
  // q = d p = R0 ray + d t0, dpx/dd = (f / q_z) (t0 - (q / q_z) t0_z).
  const Eigen::Vector3f q = R_ray + pair.t0 * d;
  const float qzi = 1.f / q.z();
  jac.dpx_didepth[0] = cam.fx * qzi * (pair.t0.x() - q.x() * qzi * pair.t0.z());
  jac.dpx_didepth[1] = cam.fy * qzi * (pair.t0.y() - q.y() * qzi * pair.t0.z());
  const float k = pair.radial_k;
  const float xt = p.x() * zi, yt = p.y() * zi;
  // Through the radial correction at the target: pixel = K D(x), dpx = K J_D K^-1 dpx_pinhole.
  Eigen::Matrix2f J = Eigen::Matrix2f::Identity();
  if (k != 0.f) {
    J = pixelRadialJacobian(cam, k, xt, yt);
    const float d0 = jac.dpx_didepth[0], d1 = jac.dpx_didepth[1];
    jac.dpx_didepth[0] = J(0, 0) * d0 + J(0, 1) * d1;
    jac.dpx_didepth[1] = J(1, 0) * d0 + J(1, 1) * d1;
  }
  if (depth_only) return;
  // dpx/dp = [[a, 0, -b], [0, c, -e]]; dp/deps = [I | -[p]x].
  const float a = cam.fx * zi, b = cam.fx * p.x() * zi * zi;
  const float c = cam.fy * zi, e = cam.fy * p.y() * zi * zi;
  float* r0 = jac.dpx_deps[0];
  float* r1 = jac.dpx_deps[1];
  r0[0] = a;
  r0[1] = 0.f;
  r0[2] = -b;
  r0[3] = -b * p.y();
  r0[4] = a * p.z() + b * p.x();
  r0[5] = -a * p.y();
  r1[0] = 0.f;
  r1[1] = c;
  r1[2] = -e;
  r1[3] = -c * p.z() - e * p.y();
  r1[4] = e * p.x();
  r1[5] = c * p.x();
  CalibJacobian host_move = CalibJacobian::Zero();
  if (dpx_dc != nullptr) {
    // The pinhole ray x_h moves by dx (z fixed): p moves by R0 (dx, 0) / d.
    const auto through = [&](float dx, float dy) {
      const Eigen::Vector3f dp = (pair.R0.col(0) * dx + pair.R0.col(1) * dy) / d;
      return Eigen::Vector2f(a * dp.x() - b * dp.z(), c * dp.y() - e * dp.z());
    };
    // k: along the host ray's radial direction |x_img| = r (1 + k r^2), so
    // dr/dk = -r^3/(1 + 3kr^2): the pinhole ray moves by s (x, y, 0), s = -r^2 / (1 + 3 k r^2).
    const float rh2 = ray.x() * ray.x() + ray.y() * ray.y();
    const float s = -rh2 / (1.f + 3.f * k * rh2);
    const Eigen::Vector3f dp = (s / d) * (R_ray - pair.R0.col(2));
    host_move.col(kCalibRadial) = Eigen::Vector2f(a * dp.x() - b * dp.z(), c * dp.y() - e * dp.z());
    // Focal scale and principal point: the image normalized coordinates m = K^-1 (u, v) of the
    // host pixel move by dm (dm/ds = -m, dm/dcx = (-1/fx, 0), dm/dcy = (0, -1/fy)), the pinhole
    // ray by J_D^-1 dm.
    if (params[kCalibFocal] || params[kCalibCx] || params[kCalibCy]) {
      const Eigen::Vector2f m = applyRadial(k, ray.x(), ray.y());
      Eigen::Matrix2f Jh = Eigen::Matrix2f::Identity();
      if (k != 0.f) Jh = radialJacobian(k, ray.x(), ray.y()).inverse();
      const Eigen::Vector2f ds = Jh * (-m);
      const Eigen::Vector2f dcx = Jh.col(0) * (-cam.fxi);
      const Eigen::Vector2f dcy = Jh.col(1) * (-cam.fyi);
      if (params[kCalibFocal]) host_move.col(kCalibFocal) = through(ds.x(), ds.y());
      if (params[kCalibCx]) host_move.col(kCalibCx) = through(dcx.x(), dcx.y());
      if (params[kCalibCy]) host_move.col(kCalibCy) = through(dcy.x(), dcy.y());
    }
  }
  if (k != 0.f) {
    for (int j = 0; j < 6; ++j) {
      const float a0 = r0[j], a1 = r1[j];
      r0[j] = J(0, 0) * a0 + J(0, 1) * a1;
      r1[j] = J(1, 0) * a0 + J(1, 1) * a1;
    }
    if (dpx_dc != nullptr) host_move = J * host_move;
  }
  if (dpx_dc != nullptr) {
    // The target's own projection pixel = K D(x_t): d/dk = K (x r^2), d/ds = K D(x_t) - c,
    // d/dc = identity.
    const float rt2 = xt * xt + yt * yt;
    const Eigen::Vector2f Dt = applyRadial(k, xt, yt);
    *dpx_dc = host_move;
    if (params[kCalibRadial])
      dpx_dc->col(kCalibRadial) += Eigen::Vector2f(cam.fx * xt * rt2, cam.fy * yt * rt2);
    if (params[kCalibFocal])
      dpx_dc->col(kCalibFocal) += Eigen::Vector2f(cam.fx * Dt.x(), cam.fy * Dt.y());
    if (params[kCalibCx]) (*dpx_dc)(0, kCalibCx) += 1.f;
    if (params[kCalibCy]) (*dpx_dc)(1, kCalibCy) += 1.f;
  }
}

/// The calibration terms of the residual's pattern (samples at the current estimate). Every
/// pixel's c, eps and depth Jacobians are the image gradient times a 2-vector shared by the
/// pattern, so the pattern needs only the gradient moments sum w g g^T, sum w g r and
/// sum w g (affine rows).
void calibrationTerms(const simd::PatternSamples& samples, const simd::PatternJacobian& jac,
                      const CalibJacobian& dc, const FramePairPrecalc& pair,
                      CalibrationResidualTerms& out) {
  float sxx = 0.f, sxy = 0.f, syy = 0.f, sxr = 0.f, syr = 0.f, sxa = 0.f, sya = 0.f, sx = 0.f,
        sy = 0.f;
  for (int i = 0; i < kPatternSize; ++i) {
    const float wx = samples.w[i] * samples.gx[i], wy = samples.w[i] * samples.gy[i];
    const float ua = jac.colors[i] - pair.host_b;
    sxx += wx * samples.gx[i];
    sxy += wx * samples.gy[i];
    syy += wy * samples.gy[i];
    sxr += wx * samples.r[i];
    syr += wy * samples.r[i];
    sxa += wx * ua;
    sya += wy * ua;
    sx += wx;
    sy += wy;
  }
  for (int p = 0; p < kCalibParams; ++p) {
    if (!out.params[p]) continue;
    const double dx = dc(0, p), dy = dc(1, p);
    // sum w J_p (g . a) for a pixel displacement a: dc_p^T S a with S the gradient moments.
    const double kx = dx * sxx + dy * sxy;
    const double ky = dx * sxy + dy * syy;
    for (int q = 0; q < kCalibParams; ++q)
      if (out.params[q]) out.H_cc(p, q) = kx * dc(0, q) + ky * dc(1, q);
    out.b_c[p] = dx * sxr + dy * syr;
    out.H_dc[p] = kx * jac.dpx_didepth[0] + ky * jac.dpx_didepth[1];
    for (int j = 0; j < 6; ++j)
      out.coupling(j, p) = kx * jac.dpx_deps[0][j] + ky * jac.dpx_deps[1][j];
    const double ka = dx * sxa + dy * sya;
    const double k1 = dx * sx + dy * sy;
    out.coupling(6, p) = pair.scale * ka;
    out.coupling(7, p) = pair.scale * k1;
    out.coupling(8, p) = -pair.scale * ka;
    out.coupling(9, p) = -k1;
  }
}

}  // namespace

float evaluateResidual(const ActivePoint& point, PointResidual& res, const FramePairPrecalc& pair,
                       const ResidualSettings& settings, ResidualAccumulator* acc) {
  return evaluateResidual(point, hostRayPixel(pair.cam, pair.radial_k, point.u, point.v), res, pair,
                          settings, acc);
}

float evaluateResidual(const ActivePoint& point, const Eigen::Vector2f& host, PointResidual& res,
                       const FramePairPrecalc& pair, const ResidualSettings& settings,
                       ResidualAccumulator* acc) {
  const int w = pair.target_image.width;
  const int h = pair.target_image.height;
  const float d = point.idepth;

  // Centre projection at the current estimate (visibility, reported projection).
  const Eigen::Vector3f pc = pair.KRKi * Eigen::Vector3f(host.x(), host.y(), 1.f) + pair.Kt * d;
  if (!(pc.z() > 0.f)) {
    res.state = ResidualState::OutOfBounds;
    return res.energy = 0.f;
  }
  Eigen::Vector2f shift = Eigen::Vector2f::Zero();
  if (pair.radial_k != 0.f) {
    const LevelCamera& cam = pair.cam;
    const float x = cam.fxi * pc.x() / pc.z() + cam.cxi, y = cam.fyi * pc.y() / pc.z() + cam.cyi;
    const float kr = pair.radial_k * (x * x + y * y);
    shift = {cam.fx * x * kr, cam.fy * y * kr};
  }
  res.projection = Eigen::Vector2f(pc.x() / pc.z(), pc.y() / pc.z()) + shift;
  if (!isInsideForBilinear(res.projection.x(), res.projection.y(), w, h,
                           settings.border + kPatternPadding)) {
    res.state = ResidualState::OutOfBounds;
    return res.energy = 0.f;
  }

  const float c = settings.gradient_weight_c;
  simd::PatternWeighting weighting;
  weighting.gradient_c2 = c * c;
  weighting.huber = settings.huber_threshold;
  weighting.margin = settings.border;
  simd::PatternPoint pattern_point;
  pattern_point.u = host.x();
  pattern_point.v = host.y();
  pattern_point.shift_x = shift.x();
  pattern_point.shift_y = shift.y();
  pattern_point.idepth = d;
  pattern_point.colors = point.colors;
  pattern_point.grad_weights = point.grad_weights;
  simd::PatternSamples samples;
  if (!simd::samplePattern<simd::Vec4>(pair.sampling, weighting, pattern_point, samples)) {
    res.state = ResidualState::OutOfBounds;
    return res.energy = 0.f;
  }
  const float energy = samples.energy;
  res.energy = energy;
  if (energy > outlierEnergy(pair, settings)) {
    res.state = ResidualState::Outlier;
    return energy;
  }
  res.state = ResidualState::Inlier;
  if (acc == nullptr) return energy;

  simd::PatternJacobian jac;
  CalibJacobian dpx_dc;
  const bool calibration = acc->calibration != nullptr && !acc->depth_only;
  centreJacobian(host.x(), host.y(), d, pair, jac, calibration ? &dpx_dc : nullptr,
                 calibration ? acc->calibration->params : CalibMask{}, acc->depth_only);
  if (acc->depth_only) {
    float H_dd, b_d;
    simd::accumulateDepthOnly<simd::Vec4>(samples, jac.dpx_didepth, &H_dd, &b_d);
    acc->H_dd += H_dd;
    acc->b_d += b_d;
    return energy;
  }
  jac.colors = point.colors;
  jac.scale = pair.scale;
  jac.host_b = pair.host_b;
  if (calibration) calibrationTerms(samples, jac, dpx_dc, pair, *acc->calibration);
  if (acc->calibration_only) return energy;
  simd::PatternPointSums ps;
  acc->pair->sums().add(samples, jac, ps);
  // Coupling over [eps, a_h, b_h, a_t, b_t] from the basis [eps, a_h, 1].
  for (int i = 0; i < 7; ++i) acc->coupling[i] += ps.coupling[i];
  acc->coupling[7] += static_cast<double>(pair.scale * ps.coupling[7]);
  acc->coupling[8] -= ps.coupling[6];
  acc->coupling[9] -= ps.coupling[7];
  acc->H_dd += ps.H_dd;
  acc->b_d += ps.b_d;
  return energy;
}

float adaptiveOutlierEnergy(std::vector<float>& pattern_energies) {
  constexpr double kQuantile = 0.7;
  constexpr double kBaseRms = 9.19;
  constexpr double kPercentileFactor = 1.5;
  if (pattern_energies.size() < 20) return 0.f;
  const auto nth = pattern_energies.begin() +
                   static_cast<std::ptrdiff_t>(kQuantile * (pattern_energies.size() - 1));
  std::nth_element(pattern_energies.begin(), nth, pattern_energies.end());
  const double rms = std::sqrt(std::max(0.0, static_cast<double>(*nth)) / kPatternSize);
  const double th = 0.5 * (kBaseRms + kPercentileFactor * rms);
  return static_cast<float>(th * th * kPatternSize);
}

}  // namespace ldsm
