#include "backend/photometric_residual.h"

#include <cmath>

#include "ldsm/image/interpolation.h"

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
  target_image = target.pyramid().gradients(0);
}

float evaluateResidual(const ActivePoint& point, PointResidual& res, const FramePairPrecalc& pair,
                       const ResidualSettings& settings, ResidualAccumulator* acc) {
  const LevelCamera& cam = pair.cam;
  const float w = static_cast<float>(pair.target_image.width);
  const float h = static_cast<float>(pair.target_image.height);
  const float d = point.idepth;

  // Centre projection at the current estimate (visibility, reported projection).
  const Eigen::Vector3f pc = pair.KRKi * Eigen::Vector3f(point.u, point.v, 1.f) + pair.Kt * d;
  if (!(pc.z() > 0.f)) {
    res.state = ResidualState::OutOfBounds;
    return res.energy = 0.f;
  }
  res.projection = {pc.x() / pc.z(), pc.y() / pc.z()};
  if (!isInsideForBilinear(res.projection.x(), res.projection.y(), static_cast<int>(w),
                           static_cast<int>(h), settings.border + kPatternPadding)) {
    res.state = ResidualState::OutOfBounds;
    return res.energy = 0.f;
  }

  // Geometric Jacobians of the centre pixel at the linearisation point (FEJ).
  Eigen::Matrix<float, 2, 6> dpx_deps = Eigen::Matrix<float, 2, 6>::Zero();
  Eigen::Vector2f dpx_dd = Eigen::Vector2f::Zero();
  if (acc != nullptr) {
    const Eigen::Vector3f ray = cam.unproject(point.u, point.v);
    const Eigen::Vector3f p = pair.R0 * ray / d + pair.t0;  // point in target, metric
    const float zi = 1.f / p.z();
    Eigen::Matrix<float, 2, 3> dpx_dp;
    dpx_dp << cam.fx * zi, 0.f, -cam.fx * p.x() * zi * zi, 0.f, cam.fy * zi,
        -cam.fy * p.y() * zi * zi;
    Eigen::Matrix<float, 3, 6> dp_deps;
    dp_deps << 1.f, 0.f, 0.f, 0.f, p.z(), -p.y(), 0.f, 1.f, 0.f, -p.z(), 0.f, p.x(), 0.f, 0.f,
        1.f, p.y(), -p.x(), 0.f;
    dpx_deps = dpx_dp * dp_deps;
    dpx_dd = dpx_dp * (-(p - pair.t0) / d);
  }

  const float c = settings.gradient_weight_c;
  const float th = settings.huber_threshold;
  float energy = 0.f;
  struct PixelTerm {
    float r, weight, gx, gy, color;
  };
  PixelTerm terms[kPatternSize];
  for (int k = 0; k < kPatternSize; ++k) {
    const float hu = point.u + static_cast<float>(kPatternOffsets[k][0]);
    const float hv = point.v + static_cast<float>(kPatternOffsets[k][1]);
    const Eigen::Vector3f q = pair.KRKi * Eigen::Vector3f(hu, hv, 1.f) + pair.Kt * d;
    const float x = q.x() / q.z();
    const float y = q.y() / q.z();
    if (!(q.z() > 0.f) || !isInsideForBilinear(x, y, static_cast<int>(w), static_cast<int>(h),
                                               settings.border)) {
      res.state = ResidualState::OutOfBounds;
      return res.energy = 0.f;
    }
    const GradientPixel g = interpolateBilinear(pair.target_image, x, y);
    const float r = g.intensity - pair.scale * point.colors[k] - pair.offset;
    const float gw = 0.5f * (gradientWeightSqrt(g.dx, g.dy, c) + point.grad_weights[k]);
    const float ar = std::fabs(r);
    const float hw = ar < th ? 1.f : th / ar;
    energy += gw * gw * (ar < th ? r * r : 2.f * th * ar - th * th);
    terms[k] = {r, gw * gw * hw, g.dx, g.dy, point.colors[k]};
  }
  res.energy = energy;
  if (energy > settings.outlier_energy) {
    res.state = ResidualState::Outlier;
    return energy;
  }
  res.state = ResidualState::Inlier;
  if (acc == nullptr) return energy;

  if (acc->depth_only) {
    for (int k = 0; k < kPatternSize; ++k) {
      const PixelTerm& t = terms[k];
      const float Jd = t.gx * dpx_dd.x() + t.gy * dpx_dd.y();
      acc->H_dd += static_cast<double>(t.weight * Jd * Jd);
      acc->b_d += static_cast<double>(t.weight * Jd * t.r);
    }
    return energy;
  }
  // Jacobian rows [eps (6), a_h, b_h, a_t, b_t, idepth, 0] per pattern pixel, summed as outer
  // products in a 12x12 float block (padded so that the columns vectorise).
  using Vec12 = Eigen::Matrix<float, 12, 1>;
  Eigen::Matrix<float, 12, 12> Hf = Eigen::Matrix<float, 12, 12>::Zero();
  Vec12 bf = Vec12::Zero();
  Vec12 J;
  J[11] = 0.f;
  J[9] = -1.f;  // b_t
  for (int k = 0; k < kPatternSize; ++k) {
    const PixelTerm& t = terms[k];
    J.head<6>() = dpx_deps.row(0).transpose() * t.gx + dpx_deps.row(1).transpose() * t.gy;
    const float dc = pair.scale * (t.color - pair.host_b);
    J[6] = dc;          // a_h
    J[7] = pair.scale;  // b_h
    J[8] = -dc;         // a_t
    J[10] = t.gx * dpx_dd.x() + t.gy * dpx_dd.y();
    const Vec12 wJ = t.weight * J;
    Hf.noalias() += wJ.lazyProduct(J.transpose());
    bf += wJ * t.r;
  }
  *acc->H_pair += Hf.topLeftCorner<kRelParams, kRelParams>().cast<double>();
  *acc->b_pair += bf.head<kRelParams>().cast<double>();
  acc->coupling += Hf.block<kRelParams, 1>(0, kRelParams).cast<double>();
  acc->H_dd += Hf(kRelParams, kRelParams);
  acc->b_d += bf[kRelParams];
  return energy;
}

}  // namespace ldsm
