#include "frontend/coarse_tracker.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <string>

#include "camera/radial_distortion.h"
#include "frontend/coarse_evaluation_sums.h"
#include "image/interpolation.h"
#include "kernels/coarse_warp.h"
#include "kernels/coarse_weigh.h"
#include "ldsm/error.h"

namespace ldsm {

namespace {

using simd::CoarseWarpedPoint;
using simd::CoarseWarpParams;

// Everything the warp of one level needs, in float.
CoarseWarpParams makeLevelWarp(const LevelCamera& cam, const SE3d& T,
                               const Eigen::Vector2d& transfer, double b_ref,
                               const AffineLight& affine, ImageView<const GradientPixel> image,
                               float margin, float radial_k) {
  CoarseWarpParams w;
  const Eigen::Matrix3f K = cam.K();
  Eigen::Matrix3f Ki;
  Ki << cam.fxi, 0, cam.cxi, 0, cam.fyi, cam.cyi, 0, 0, 1;
  const Eigen::Matrix3f KRKi = K * T.rotationMatrix().cast<float>() * Ki;
  const Eigen::Vector3f Kt = K * T.translation().cast<float>();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) w.KRKi[3 * r + c] = KRKi(r, c);
    w.Kt[r] = Kt(r);
  }
  w.fx = cam.fx;
  w.fy = cam.fy;
  w.fxi = cam.fxi;
  w.fyi = cam.fyi;
  w.cxi = cam.cxi;
  w.cyi = cam.cyi;
  w.cx = cam.cx;
  w.cy = cam.cy;
  w.radial_k = radial_k;
  w.margin = margin;
  w.scale = static_cast<float>(transfer(0));
  w.b_ref = static_cast<float>(b_ref);
  w.b = static_cast<float>(affine.b);
  w.image = image;
  return w;
}

void checkExposure(double exposure, const char* what) {
  if (!(exposure > 0.0) || !std::isfinite(exposure)) {
    throw InputError(std::string("coarse tracker: ") + what +
                     " exposure must be finite and > 0 (got " + std::to_string(exposure) + ")");
  }
}

}  // namespace

const char* toString(TrackingFailure failure) {
  switch (failure) {
    case TrackingFailure::kNone:
      return "none";
    case TrackingFailure::kNoReference:
      return "no reference points";
    case TrackingFailure::kTooFewInImage:
      return "too few points in the image";
    case TrackingFailure::kNotFinite:
      return "residual not finite";
    case TrackingFailure::kResidualTooLarge:
      return "residual above abort threshold";
    case TrackingFailure::kAffineOutOfRange:
      return "affine brightness out of range";
    case TrackingFailure::kTooFewInliers:
      return "too few inlier residuals";
  }
  return "unknown";
}

double CoarseTracker::Evaluation::rmse() const {
  return in_image > 0 ? std::sqrt(huber_sq_sum / in_image)
                      : std::numeric_limits<double>::infinity();
}

double CoarseTracker::Evaluation::meanEnergy() const {
  return in_image > 0 ? energy / in_image : std::numeric_limits<double>::infinity();
}

CoarseTracker::CoarseTracker(int width, int height, int levels,
                             const CoarseTrackerSettings& settings)
    : settings_(settings), depth_maps_(width, height, levels) {
  if (!(settings.huber_threshold > 0.f) || !std::isfinite(settings.huber_threshold)) {
    throw ConfigError("coarse tracker: huber_threshold must be finite and > 0");
  }
  if (!(settings.outlier_threshold > 0.f) || !std::isfinite(settings.outlier_threshold)) {
    throw ConfigError("coarse tracker: outlier_threshold must be finite and > 0");
  }
  if (!(settings.coarse_level_min_relative_decrease >= 0.0 &&
        settings.coarse_level_min_relative_decrease < 1.0)) {
    throw ConfigError("coarse tracker: coarse_level_min_relative_decrease must be in [0, 1)");
  }
}

void CoarseTracker::setReference(const ImagePyramid& reference, const PyramidCamera& camera,
                                 const DepthPoint* points, std::size_t count, double exposure,
                                 const AffineLight& affine, DepthMapCanvas* canvas,
                                 float radial_k) {
  checkExposure(exposure, "reference");
  if (!std::isfinite(radial_k))
    throw InputError("coarse tracker: radial_k must be finite (got " + std::to_string(radial_k) +
                     ")");
  if (camera.levels() < levels() || camera[0].width != depth_maps_.width(0) ||
      camera[0].height != depth_maps_.height(0)) {
    throw InputError("coarse tracker: camera is " + std::to_string(camera[0].width) + "x" +
                     std::to_string(camera[0].height) + " with " + std::to_string(camera.levels()) +
                     " levels, expected " + std::to_string(depth_maps_.width(0)) + "x" +
                     std::to_string(depth_maps_.height(0)) + " with at least " +
                     std::to_string(levels()) + " levels");
  }
  if (canvas != nullptr)
    depth_maps_.build(points, count, reference, *canvas);
  else
    depth_maps_.build(points, count, reference);
  // The residual buffer holds one level's points at a time: it grows (here, never while tracking)
  // to the largest level seen, with a quarter of slack.
  std::size_t most = 0;
  for (int l = 0; l < levels(); ++l)
    most = std::max(most, static_cast<std::size_t>(depth_maps_.points(l).count));
  if (warped_.dx_fx.size() < most) warped_.allocate(most + most / 4);
  camera_ = camera;
  radial_k_ = radial_k;
  if (radial_k != 0.f) {
    for (int l = 0; l < levels(); ++l) {
      const LevelPoints& pts = depth_maps_.points(l);
      const LevelCamera& cam = camera[l];
      const std::size_t points_here = static_cast<std::size_t>(pts.count);
      if (ray_x_[l].size() < points_here) {  // grows like the residual buffer, with slack
        ray_x_[l].resize(points_here + points_here / 4);
        ray_y_[l].resize(points_here + points_here / 4);
      }
      for (int i = 0; i < pts.count; ++i) {
        const Eigen::Vector2f n =
            removeRadial(radial_k, cam.fxi * pts.x[i] + cam.cxi, cam.fyi * pts.y[i] + cam.cyi);
        ray_x_[l][i] = cam.fx * n.x() + cam.cx;
        ray_y_[l][i] = cam.fy * n.y() + cam.cy;
      }
    }
  }
  ref_exposure_ = exposure;
  ref_affine_ = affine;
  reference_cells_.reset();
  const LevelPoints& pts = depth_maps_.points(0);
  for (int i = 0; i < pts.count; ++i)
    if (const int c = coverageCell(pts.x[i], pts.y[i]); c >= 0)
      reference_cells_.set(static_cast<std::size_t>(c));
  has_reference_ = true;
}

double CoarseTracker::scaleOf(double exposure, const AffineLight& affine) const {
  return affineTransfer(ref_exposure_, exposure, ref_affine_, affine)(0);
}

const float* CoarseTracker::rayX(int level) const {
  return radial_k_ != 0.f ? ray_x_[level].data() : depth_maps_.points(level).x.data();
}

const float* CoarseTracker::rayY(int level) const {
  return radial_k_ != 0.f ? ray_y_[level].data() : depth_maps_.points(level).y.data();
}

CoarseTracker::Evaluation CoarseTracker::evaluate(const ImagePyramid& frame, double exposure,
                                                  int level, const SE3d& T,
                                                  const AffineLight& affine, float cutoff) {
  return radial_k_ != 0.f ? evaluateLevel<true>(frame, exposure, level, T, affine, cutoff)
                          : evaluateLevel<false>(frame, exposure, level, T, affine, cutoff);
}

template <bool kRadial>
CoarseTracker::Evaluation CoarseTracker::evaluateLevel(const ImagePyramid& frame, double exposure,
                                                       int level, const SE3d& T,
                                                       const AffineLight& affine, float cutoff) {
  const CoarseWarpParams w = makeLevelWarp(
      camera_[level], T, affineTransfer(ref_exposure_, exposure, ref_affine_, affine),
      ref_affine_.b, affine, frame.gradients(level), settings_.border_margin, radial_k_);
  const LevelPoints& pts = depth_maps_.points(level);
  const float* rx = rayX(level);
  const float* ry = rayY(level);
  const float c2 = settings_.gradient_weight_c * settings_.gradient_weight_c;
  const float k = settings_.huber_threshold;
  const float base_cutoff = settings_.outlier_threshold;
  // Cost of an outlier: the Huber cost at the cutoff, so the cost is continuous there.
  const float outlier_cost = cutoff > k ? 2.f * k * cutoff - k * k : cutoff * cutoff;
  simd::CoarseWeighting weighting;
  weighting.c2 = c2;
  weighting.huber = k;
  weighting.cutoff = cutoff;
  weighting.outlier_cost = outlier_cost;
  weighting.base_cutoff = base_cutoff;
  CoarseEvaluationSums sums(warped_);
  int i = 0;
  simd::CoarseWarp4 block;
  simd::CoarseWeights4 weights;
  for (; i + 4 <= pts.count; i += 4) {
    simd::warpCoarse4<simd::Vec4, kRadial>(w, rx + i, ry + i, &pts.idepth[i], &pts.intensity[i],
                                           block);
    if (block.inside == 0) continue;
    simd::weighCoarse4<simd::Vec4>(weighting, block.residual, &pts.grad_sq[i], weights);
    sums.addBlock(block, weights);
  }
  for (; i < pts.count; ++i) {
    CoarseWarpedPoint wp;
    if (simd::reference::warpCoarsePoint<kRadial>(w, rx[i], ry[i], pts.idepth[i], pts.intensity[i],
                                                  wp))
      sums.addPoint(wp, simd::reference::weighCoarsePoint(weighting, wp.residual, pts.grad_sq[i]));
  }
  sums.finish();
  Evaluation ev;
  ev.energy = sums.energy();
  ev.huber_sq_sum = sums.huberSum();
  ev.in_image = sums.inImage();
  ev.outliers = sums.outliers();
  ev.base_inliers = sums.inImage() - sums.baseOutliers();
  ev.inliers = sums.inliers();
  ev.finite = std::isfinite(ev.energy);
  return ev;
}

void CoarseTracker::addAffinePrior(const AffineLight& affine, int points, CoarseMatrix& H,
                                   CoarseVector& g) const {
  const double n = static_cast<double>(points);
  const double wa = n * settings_.affine_change_prior_a;
  const double wb = n * settings_.affine_change_prior_b;
  H(6, 6) += settings_.affine_prior_weight_a + wa;
  H(7, 7) += settings_.affine_prior_weight_b + wb;
  g(6) += settings_.affine_prior_weight_a * (affine.a - ref_affine_.a) +
          wa * (affine.a - predicted_affine_.a);
  g(7) += settings_.affine_prior_weight_b * (affine.b - ref_affine_.b) +
          wb * (affine.b - predicted_affine_.b);
}

double CoarseTracker::affinePriorEnergy(const AffineLight& affine, int points) const {
  const double da = affine.a - ref_affine_.a;
  const double db = affine.b - ref_affine_.b;
  const double pa = affine.a - predicted_affine_.a;
  const double pb = affine.b - predicted_affine_.b;
  return (settings_.affine_prior_weight_a * da * da + settings_.affine_prior_weight_b * db * db) /
             std::max(points, 1) +
         settings_.affine_change_prior_a * pa * pa + settings_.affine_change_prior_b * pb * pb;
}

CoarseTracker::Evaluation CoarseTracker::optimiseLevel(const ImagePyramid& frame, double exposure,
                                                       int level, bool refined_further, SE3d& T,
                                                       AffineLight& affine, float& cutoff,
                                                       int& iterations) {
  const int count = depth_maps_.points(level).count;
  const auto usable = [&](const Evaluation& e) {
    return e.finite && e.inliers > 0 &&
           static_cast<float>(e.in_image) >= settings_.min_in_image_fraction * count;
  };
  Evaluation ev = evaluate(frame, exposure, level, T, affine, cutoff);
  if (!usable(ev)) return ev;
  for (int d = 0; d < settings_.max_threshold_doublings &&
                  ev.outliers > settings_.outlier_fraction_for_doubling * ev.in_image;
       ++d) {
    cutoff *= 2.f;
    ev = evaluate(frame, exposure, level, T, affine, cutoff);
  }
  // The total cost compared between steps: mean data energy plus the prior spread the same way.
  const auto cost = [&](const Evaluation& e, const AffineLight& aff) {
    return e.meanEnergy() + affinePriorEnergy(aff, e.in_image);
  };
  CoarseMatrix H;
  CoarseVector g;
  accumulateNormalEquations(warped_, H, g);
  addAffinePrior(affine, ev.in_image, H, g);
  double current_cost = cost(ev, affine);
  double lambda = settings_.initial_lambda;
  int rejected_in_a_row = 0;
  for (int it = 0; it < settings_.max_iterations[level]; ++it) {
    // Jacobi scaling makes the diagonal 1, so rotation, translation, a and b are comparable.
    const CoarseVector D = (H.diagonal().array().max(1e-12)).sqrt().inverse().matrix();
    CoarseMatrix A = D.asDiagonal() * H * D.asDiagonal();
    A.diagonal().array() += lambda;
    const CoarseVector step_scaled = -A.ldlt().solve(D.asDiagonal() * g);
    if (!step_scaled.allFinite()) break;
    // sum_i H_ii step_i^2 / n: roughly the mean squared change of the residuals.
    const double rms_step = std::sqrt(step_scaled.squaredNorm() / std::max(ev.inliers, 1));
    if (rms_step < settings_.convergence_rms_step) break;
    const CoarseVector step = D.asDiagonal() * step_scaled;
    const SE3d T_new = SE3d::exp(step.head<6>()) * T;
    const AffineLight affine_new{affine.a + step(6), affine.b + step(7)};
    const Evaluation ev_new = evaluate(frame, exposure, level, T_new, affine_new, cutoff);
    ++iterations;
    if (usable(ev_new) && cost(ev_new, affine_new) < current_cost) {
      T = T_new;
      affine = affine_new;
      ev = ev_new;
      const double previous_cost = current_cost;
      current_cost = cost(ev, affine);
      // A step that hardly lowered the cost: close enough for the finer level to start from.
      // (Not stopping after rejected steps, whose larger damping shortens the next one, was
      // measured and not kept: docs/engine.md, "Stopping the coarse levels early".)
      const bool hardly_fell = previous_cost - current_cost <
                               settings_.coarse_level_min_relative_decrease * previous_cost;
      if (refined_further && hardly_fell) {
        break;
      }
      accumulateNormalEquations(warped_, H, g);
      addAffinePrior(affine, ev.in_image, H, g);
      lambda = std::max(lambda * 0.5, 1e-8);
      rejected_in_a_row = 0;
    } else {
      // Repeated failures to descend: the minimum is reached as far as the data can tell.
      if (++rejected_in_a_row >= settings_.max_rejected_steps) break;
      lambda *= 4.0;
    }
  }
  return ev;
}

bool CoarseTracker::track(const ImagePyramid& frame, double exposure, SE3d& T_frame_ref,
                          AffineLight& affine, int coarsest_level, const LevelValues& max_rmse,
                          CoarseTrackingResult& result, int finest_level) {
  result = CoarseTrackingResult();
  checkExposure(exposure, "frame");
  predicted_affine_ = affine;
  if (frame.width(0) != depth_maps_.width(0) || frame.height(0) != depth_maps_.height(0) ||
      frame.levels() < levels()) {
    throw InputError("coarse tracker: frame pyramid is " + std::to_string(frame.width(0)) + "x" +
                     std::to_string(frame.height(0)) + " with " + std::to_string(frame.levels()) +
                     " levels, expected " + std::to_string(depth_maps_.width(0)) + "x" +
                     std::to_string(depth_maps_.height(0)) + " with at least " +
                     std::to_string(levels()) + " levels");
  }
  const auto fail = [&](TrackingFailure why, int level) {
    result.success = false;
    result.failure = why;
    result.failed_level = level;
    return false;
  };
  if (!has_reference_) return fail(TrackingFailure::kNoReference, levels() - 1);
  const int coarsest = std::clamp(coarsest_level, 0, levels() - 1);
  const int finest = std::clamp(finest_level, 0, coarsest);
  bool repeated = false;
  Evaluation ev;
  for (int level = coarsest; level >= finest; --level) {
    if (depth_maps_.points(level).count == 0) return fail(TrackingFailure::kNoReference, level);
    float cutoff = settings_.outlier_threshold;
    ev = optimiseLevel(frame, exposure, level, level > finest, T_frame_ref, affine, cutoff,
                       result.iterations);
    result.rmse(level) = ev.rmse();
    if (ev.in_image == 0 || static_cast<float>(ev.in_image) <
                                settings_.min_in_image_fraction * depth_maps_.points(level).count) {
      return fail(TrackingFailure::kTooFewInImage, level);
    }
    if (!ev.finite) return fail(TrackingFailure::kNotFinite, level);
    if (ev.inliers == 0) return fail(TrackingFailure::kTooFewInliers, level);
    if (!(std::abs(affine.a - ref_affine_.a) <= settings_.max_affine_a_change &&
          std::abs(affine.b - ref_affine_.b) <= settings_.max_affine_b_change)) {
      return fail(TrackingFailure::kAffineOutOfRange, level);
    }
    if (!(result.rmse(level) <= max_rmse(level))) {
      return fail(TrackingFailure::kResidualTooLarge, level);
    }
    // The outlier threshold had to grow: the start was far off. Run the level once more from the
    // improved estimate with the normal threshold (once per frame).
    if (cutoff > settings_.outlier_threshold && !repeated) {
      repeated = true;
      ++level;
    }
  }
  if (finest > 0) {
    result.success = true;
    return true;
  }
  result.in_image_fraction = static_cast<double>(ev.in_image) / depth_maps_.points(0).count;
  result.inlier_fraction = static_cast<double>(ev.base_inliers) / ev.in_image;
  result.brightness_scale = scaleOf(exposure, affine);
  computeFlow(T_frame_ref, result);
  computeCoverage(T_frame_ref, result);
  if (result.inlier_fraction < settings_.min_inlier_fraction) {
    return fail(TrackingFailure::kTooFewInliers, 0);
  }
  result.success = true;
  return true;
}

void CoarseTracker::computeFlow(const SE3d& T, CoarseTrackingResult& result) const {
  const LevelPoints& pts = depth_maps_.points(0);
  const LevelCamera& cam = camera_[0];
  const Eigen::Matrix3d R = T.rotationMatrix();
  const Eigen::Vector3d t = T.translation();
  const int stride = std::max(1, pts.count / 1000);
  double full = 0, trans = 0, rot = 0;
  int n = 0;
  const auto shift2 = [&](const Eigen::Vector3d& q, double x, double y, double& acc) {
    if (!(q.z() > 0)) return false;
    const double du = cam.fx * q.x() / q.z() + cam.cx - x;
    const double dv = cam.fy * q.y() / q.z() + cam.cy - y;
    acc += du * du + dv * dv;
    return true;
  };
  // Flow of the pinhole pixels (those of the undistorted rays with a radial distortion).
  const float* rx = rayX(0);
  const float* ry = rayY(0);
  for (int i = 0; i < pts.count; i += stride) {
    const double x = rx[i], y = ry[i];
    const Eigen::Vector3d ray(cam.fxi * x + cam.cxi, cam.fyi * y + cam.cyi, 1.0);
    const Eigen::Vector3d p = ray / pts.idepth[i];
    double f = 0, ft = 0, fr = 0;
    if (shift2(R * p + t, x, y, f) && shift2(p + t, x, y, ft) && shift2(R * ray, x, y, fr)) {
      full += f;
      trans += ft;
      rot += fr;
      ++n;
    }
  }
  if (n == 0) return;
  result.flow_full = std::sqrt(full / n);
  result.flow_translation = std::sqrt(trans / n);
  result.flow_rotation = std::sqrt(rot / n);
}

int CoarseTracker::coverageCell(float u, float v) const {
  const LevelCamera& cam = camera_[0];
  if (!(u >= 0.f && v >= 0.f && u < cam.width && v < cam.height)) return -1;
  const int column = static_cast<int>(u * (kCoverageColumns / static_cast<float>(cam.width)));
  const int row = static_cast<int>(v * (kCoverageRows / static_cast<float>(cam.height)));
  return std::min(row, kCoverageRows - 1) * kCoverageColumns +
         std::min(column, kCoverageColumns - 1);
}

void CoarseTracker::computeCoverage(const SE3d& T, CoarseTrackingResult& result) const {
  // Every level-0 point (a sample would leave cells empty that hold points).
  if (reference_cells_.none()) return;
  const LevelPoints& pts = depth_maps_.points(0);
  const LevelCamera& cam = camera_[0];
  const Eigen::Matrix3f R = T.rotationMatrix().cast<float>();
  const Eigen::Vector3f t = T.translation().cast<float>();
  std::bitset<kCoverageColumns * kCoverageRows> in_frame;
  const float* rx = rayX(0);
  const float* ry = rayY(0);
  for (int i = 0; i < pts.count; ++i) {
    const Eigen::Vector3f ray(cam.fxi * rx[i] + cam.cxi, cam.fyi * ry[i] + cam.cyi, 1.f);
    const Eigen::Vector3f q = R * (ray / pts.idepth[i]) + t;
    if (!(q.z() > 0.f)) continue;
    int c;
    if (radial_k_ != 0.f) {
      const float xn = q.x() / q.z(), yn = q.y() / q.z();
      if (!(1.f + 3.f * radial_k_ * (xn * xn + yn * yn) > 0.f)) continue;  // no image (k < 0)
      const Eigen::Vector2f px = radialProject(cam, radial_k_, q);         // the image's pixel
      c = coverageCell(px.x(), px.y());
    } else {
      c = coverageCell(cam.fx * q.x() / q.z() + cam.cx, cam.fy * q.y() / q.z() + cam.cy);
    }
    if (c >= 0) in_frame.set(static_cast<std::size_t>(c));
  }
  result.coverage =
      static_cast<double>(in_frame.count()) / static_cast<double>(reference_cells_.count());
}

bool CoarseTracker::pointResidual(const ImagePyramid& frame, double exposure,
                                  const SE3d& T_frame_ref, const AffineLight& affine, int level,
                                  int index, float* residual, float* jacobian) const {
  const LevelPoints& pts = depth_maps_.points(level);
  if (!has_reference_ || index < 0 || index >= pts.count) return false;
  const CoarseWarpParams w = makeLevelWarp(
      camera_[level], T_frame_ref, affineTransfer(ref_exposure_, exposure, ref_affine_, affine),
      ref_affine_.b, affine, frame.gradients(level), settings_.border_margin, radial_k_);
  CoarseWarpedPoint wp;
  const float x = rayX(level)[index], y = rayY(level)[index];
  const bool in = radial_k_ != 0.f ? simd::reference::warpCoarsePoint<true>(
                                         w, x, y, pts.idepth[index], pts.intensity[index], wp)
                                   : simd::reference::warpCoarsePoint<false>(
                                         w, x, y, pts.idepth[index], pts.intensity[index], wp);
  if (!in) return false;
  if (residual != nullptr) *residual = wp.residual;
  if (jacobian != nullptr) {
    coarseJacobianRow(wp.dx_fx, wp.dy_fy, wp.nx, wp.ny, wp.iz, wp.ref_term, jacobian);
  }
  return true;
}

}  // namespace ldsm
