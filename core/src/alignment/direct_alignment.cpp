#include "alignment/direct_alignment.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>

#include "camera/radial_distortion.h"
#include "image/interpolation.h"

namespace ldsm {
namespace {

using Matrix8 = Eigen::Matrix<double, 8, 8>;
using Vector8 = Eigen::Matrix<double, 8, 1>;

struct LevelEvaluation {
  double energy = 0.0;     // Huber energies of inliers + the outlier energy of each outlier point
  double inlier_sq = 0.0;  // sum of squared residuals of inlier patterns
  int in_image = 0;
  int inliers = 0;
  int inlier_pixels = 0;
  // Zero-normalised cross-correlation of host and target pattern, summed over the points in the
  // image (inliers and outliers) that have contrast in both.
  double correlation_sum = 0.0;
  int correlated = 0;
  Matrix8 H = Matrix8::Zero();
  Vector8 g = Vector8::Zero();
};

class Aligner {
 public:
  Aligner(const std::vector<PatchPoint>& points, const PyramidCamera& camera, float radial_k,
          const ImagePyramid& target, const DirectAlignmentSettings& s)
      : camera_(camera), k_(radial_k), target_(target), s_(s) {
    rays_.reserve(points.size());
    for (const PatchPoint& p : points) {
      if (!(p.idepth > 0.f) || !std::isfinite(p.idepth)) continue;
      const Eigen::Vector3f ray = radialRay(camera[0], radial_k, p.u, p.v);
      rays_.push_back({ray.cast<double>() / static_cast<double>(p.idepth), &p});
    }
  }

  std::size_t usable() const { return rays_.size(); }

  static void accumulateCorrelation(const float* host, const GradientPixel* target,
                                    LevelEvaluation& ev) {
    double mh = 0.0, mt = 0.0;
    for (int i = 0; i < kPatternSize; ++i) {
      mh += host[i];
      mt += target[i].intensity;
    }
    mh /= kPatternSize;
    mt /= kPatternSize;
    double hh = 0.0, tt = 0.0, ht = 0.0;
    for (int i = 0; i < kPatternSize; ++i) {
      const double dh = host[i] - mh, dt = target[i].intensity - mt;
      hh += dh * dh;
      tt += dt * dt;
      ht += dh * dt;
    }
    // Flat patterns (under a grey level of spread) say nothing either way.
    if (hh < kPatternSize || tt < kPatternSize) return;
    ev.correlation_sum += ht / std::sqrt(hh * tt);
    ++ev.correlated;
  }

  /// Energy (and, when `linearise`, the normal equations) at level `level`.
  LevelEvaluation evaluate(int level, const SE3d& T, double a, double b, bool linearise) const {
    LevelEvaluation ev;
    const LevelCamera& cam = camera_[level];
    const ImageView<const GradientPixel> img = target_.gradients(level);
    const double scale = std::exp(a);
    const float h = s_.huber_threshold;
    const float outlier_energy = s_.outlier_threshold * s_.outlier_threshold * kPatternSize;
    const float margin = s_.border + static_cast<float>(kPatternPadding);
    const Eigen::Matrix3d R = T.so3().matrix();
    const Eigen::Vector3d t = T.translation();
    for (const Ray& r : rays_) {
      const Eigen::Vector3d q = R * r.point + t;
      if (!(q.z() > 1e-6)) continue;
      const Eigen::Vector2f px = radialProject(cam, k_, q.cast<float>());
      if (!isInsideForBilinear(img, px.x(), px.y(), margin)) continue;
      ++ev.in_image;
      float res[kPatternSize];
      GradientPixel gp[kPatternSize];
      float e = 0.f;
      for (int i = 0; i < kPatternSize; ++i) {
        gp[i] = interpolateBilinear(img, px.x() + static_cast<float>(kPatternOffsets[i][0]),
                                    px.y() + static_cast<float>(kPatternOffsets[i][1]));
        res[i] = gp[i].intensity - static_cast<float>(scale * r.patch->colors[i] + b);
        const float ar = std::fabs(res[i]);
        e += ar <= h ? ar * ar : h * (2.f * ar - h);
      }
      accumulateCorrelation(r.patch->colors, gp, ev);
      if (!(e < outlier_energy)) {
        ev.energy += outlier_energy;
        continue;
      }
      ev.energy += e;
      ++ev.inliers;
      if (!linearise) continue;
      // d pixel / d q, with the radial distortion's own derivative.
      const double iz = 1.0 / q.z();
      const double x = q.x() * iz, y = q.y() * iz;
      const double f = 1.0 + k_ * (x * x + y * y);
      Eigen::Matrix2d D;
      D << f + 2.0 * k_ * x * x, 2.0 * k_ * x * y, 2.0 * k_ * x * y, f + 2.0 * k_ * y * y;
      Eigen::Matrix<double, 2, 3> dn;
      dn << iz, 0.0, -x * iz, 0.0, iz, -y * iz;
      Eigen::Matrix<double, 2, 3> dpx = D * dn;
      dpx.row(0) *= cam.fx;
      dpx.row(1) *= cam.fy;
      Eigen::Matrix<double, 3, 6> dq;
      dq.leftCols<3>().setIdentity();
      dq.rightCols<3>() = -SO3d::hat(q);
      const Eigen::Matrix<double, 2, 6> dpx_dxi = dpx * dq;
      for (int i = 0; i < kPatternSize; ++i) {
        Vector8 J;
        J.head<6>() = static_cast<double>(gp[i].dx) * dpx_dxi.row(0).transpose() +
                      static_cast<double>(gp[i].dy) * dpx_dxi.row(1).transpose();
        J[6] = -scale * r.patch->colors[i];
        J[7] = -1.0;
        const float ar = std::fabs(res[i]);
        const double w = ar <= h ? 1.0 : h / ar;
        ev.H.noalias() += w * J * J.transpose();
        ev.g.noalias() += w * static_cast<double>(res[i]) * J;
        ev.inlier_sq += w * static_cast<double>(res[i]) * res[i];
        ++ev.inlier_pixels;
      }
    }
    return ev;
  }

  double priorEnergy(double a, double b, int points) const {
    const double da = a - a0_, db = b - b0_;
    return points * (s_.affine_prior_a * da * da + s_.affine_prior_b * db * db);
  }
  void addPrior(LevelEvaluation& ev, double a, double b) const {
    const int n = std::max(ev.in_image, 1);
    ev.H(6, 6) += n * s_.affine_prior_a;
    ev.H(7, 7) += n * s_.affine_prior_b;
    ev.g[6] += n * s_.affine_prior_a * (a - a0_);
    ev.g[7] += n * s_.affine_prior_b * (b - b0_);
  }
  void setAffineStart(double a, double b) {
    a0_ = a;
    b0_ = b;
  }

 private:
  struct Ray {
    Eigen::Vector3d point;  // in the host camera
    const PatchPoint* patch;
  };
  const PyramidCamera& camera_;
  double k_;
  const ImagePyramid& target_;
  const DirectAlignmentSettings& s_;
  std::vector<Ray> rays_;
  double a0_ = 0.0, b0_ = 0.0;
};

}  // namespace

DirectAlignmentResult alignPoints(const std::vector<PatchPoint>& points,
                                  const PyramidCamera& camera, float radial_k,
                                  const ImagePyramid& target, const SE3d& T_initial,
                                  double a_initial, double b_initial,
                                  const DirectAlignmentSettings& settings) {
  DirectAlignmentResult out;
  out.T_target_host = T_initial;
  out.a = a_initial;
  out.b = b_initial;
  Aligner aligner(points, camera, radial_k, target, settings);
  aligner.setAffineStart(a_initial, b_initial);
  if (static_cast<int>(aligner.usable()) < settings.min_points) {
    out.failure = "only " + std::to_string(aligner.usable()) + " points with depth";
    return out;
  }
  const int levels = std::min(camera.levels(), target.levels());
  SE3d T = T_initial;
  double a = a_initial, b = b_initial;
  LevelEvaluation last;
  for (int level = std::clamp(settings.coarsest_level, 0, levels - 1); level >= 0; --level) {
    LevelEvaluation cur = aligner.evaluate(level, T, a, b, true);
    if (cur.in_image < std::max(8, settings.min_points / (1 << (2 * level)))) {
      out.failure = "too few points in the image at level " + std::to_string(level);
      return out;
    }
    double energy = cur.energy + aligner.priorEnergy(a, b, cur.in_image);
    aligner.addPrior(cur, a, b);
    double lambda = 1e-3;
    for (int it = 0; it < settings.max_iterations; ++it) {
      ++out.iterations;
      Matrix8 A = cur.H;
      for (int i = 0; i < 8; ++i) A(i, i) = cur.H(i, i) * (1.0 + lambda) + 1e-9;
      const Vector8 step = -A.ldlt().solve(cur.g);
      if (!step.allFinite()) break;
      const SE3d T_new = SE3d::exp(step.head<6>()) * T;
      const double a_new = a + step[6], b_new = b + step[7];
      LevelEvaluation next = aligner.evaluate(level, T_new, a_new, b_new, true);
      const double e_new = next.energy + aligner.priorEnergy(a_new, b_new, next.in_image);
      if (next.in_image >= cur.in_image / 2 && e_new < energy) {
        T = T_new;
        a = a_new;
        b = b_new;
        energy = e_new;
        aligner.addPrior(next, a, b);
        cur = next;
        lambda = std::max(lambda * 0.5, 1e-6);
        if (step.head<6>().norm() < settings.convergence_step) break;
      } else {
        lambda *= 4.0;
        if (lambda > 1e4) break;
      }
    }
    last = cur;
  }
  out.T_target_host = T;
  out.a = a;
  out.b = b;
  out.in_image = last.in_image;
  out.inliers = last.inliers;
  out.rmse = last.inlier_pixels > 0 ? std::sqrt(last.inlier_sq / last.inlier_pixels) : 0.0;
  out.pattern_correlation = last.correlated > 0 ? last.correlation_sum / last.correlated : 0.0;
  if (last.in_image < settings.min_points) {
    out.failure = "only " + std::to_string(last.in_image) + " points in the image";
    return out;
  }
  if (last.inliers < settings.min_inlier_fraction * last.in_image) {
    out.failure = "only " + std::to_string(last.inliers) + " of " + std::to_string(last.in_image) +
                  " points are inliers";
    return out;
  }
  // Information of the pose: the affine parameters eliminated (Schur), whitened by the
  // residuals' a-posteriori variance, one pattern counted as one measurement.
  const double dof = std::max(1, last.inlier_pixels - 8);
  const double variance = std::max(last.inlier_sq / dof, 1e-6);
  const Eigen::Matrix<double, 6, 6> Hpp = last.H.topLeftCorner<6, 6>();
  const Eigen::Matrix<double, 6, 2> Hpa = last.H.topRightCorner<6, 2>();
  const Eigen::Matrix2d Haa = last.H.bottomRightCorner<2, 2>();
  const Eigen::Matrix<double, 6, 6> schur = Hpp - Hpa * Haa.ldlt().solve(Hpa.transpose());
  out.information = schur / (variance * kPatternSize);
  out.success = out.information.allFinite();
  if (!out.success) out.failure = "information not finite";
  return out;
}

}  // namespace ldsm
