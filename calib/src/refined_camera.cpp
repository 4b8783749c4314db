#include "ldsm/calib/refined_camera.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <vector>

#include "ldsm/calib/dso_camera_file.h"
#include "ldsm/calib/kalibr_yaml.h"
#include "ldsm/camera/camera_model.h"
#include "ldsm/camera/rectifier.h"
#include "ldsm/error.h"

namespace ldsm::calib {
namespace {

struct RaySample {
  Eigen::Vector2d pixel;  ///< input image
  Eigen::Vector3d ray;    ///< the refined camera's ray through it
};

bool samePinhole(const PinholeIntrinsics& a, const PinholeIntrinsics& b) {
  const auto close = [](double x, double y) {
    return std::abs(x - y) <= 1e-6 * std::max(1.0, std::abs(x));
  };
  return a.width == b.width && a.height == b.height && close(a.fx, b.fx) && close(a.fy, b.fy) &&
         close(a.cx, b.cx) && close(a.cy, b.cy);
}

/// The r with r (1 + k r^2) = rho (Newton from rho); false where the radial map folds over.
bool removeRadial(double k, double rho, double* r) {
  double x = rho;
  for (int i = 0; i < 30; ++i) {
    const double d = 1.0 + 3.0 * k * x * x;
    if (d < 0.2) return false;
    const double step = (x * (1.0 + k * x * x) - rho) / d;
    x -= step;
    if (std::abs(step) < 1e-14 * std::max(1.0, rho)) break;
  }
  if (std::abs(x * (1.0 + k * x * x) - rho) > 1e-10 * std::max(1.0, rho)) return false;
  *r = x;
  return true;
}

/// Input pixels on a grid over the part of the input image the engine sees (its rectified
/// output), each with the ray the refined camera gives it.
std::vector<RaySample> refinedRays(const CameraModel& input, const PinholeIntrinsics& k0,
                                   const PinholeIntrinsics& ka, double k) {
  std::vector<RaySample> samples;
  const int nx = 48;
  const int ny = std::max(12, static_cast<int>(std::lround(48.0 * input.height() / input.width())));
  samples.reserve(static_cast<size_t>(nx * ny));
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const Eigen::Vector2d u((input.width() - 1) * (i / (nx - 1.0)),
                              (input.height() - 1) * (j / (ny - 1.0)));
      Eigen::Vector3d ray;
      if (!input.unproject(u, &ray) || ray.z() < 1e-6) continue;
      const Eigen::Vector2d n0 = ray.head<2>() / ray.z();
      const Eigen::Vector2d p0(k0.fx * n0.x() + k0.cx, k0.fy * n0.y() + k0.cy);
      if (p0.x() < -0.5 || p0.y() < -0.5 || p0.x() > k0.width - 0.5 || p0.y() > k0.height - 0.5)
        continue;
      const Eigen::Vector2d y((p0.x() - ka.cx) / ka.fx, (p0.y() - ka.cy) / ka.fy);
      const double rho = y.norm();
      double r = rho;
      if (rho > 0.0 && !removeRadial(k, rho, &r)) continue;
      const Eigen::Vector2d x = rho > 0.0 ? Eigen::Vector2d(y * (r / rho)) : y;
      samples.push_back({u, Eigen::Vector3d(x.x(), x.y(), 1.0).normalized()});
    }
  }
  return samples;
}

/// Sum of squared reprojection errors of `model` over the samples (infinity where one fails).
double fitCost(const CameraModel& model, const std::vector<RaySample>& samples) {
  double cost = 0.0;
  for (const RaySample& s : samples) {
    Eigen::Vector2d px;
    if (!model.project(s.ray, &px)) return std::numeric_limits<double>::infinity();
    cost += (px - s.pixel).squaredNorm();
  }
  return cost;
}

/// Levenberg-Marquardt over all intrinsic parameters of `model`.
std::unique_ptr<CameraModel> fitModel(std::unique_ptr<CameraModel> model,
                                      const std::vector<RaySample>& samples) {
  const int n = model->numParameters();
  double cost = fitCost(*model, samples);
  double lambda = 1e-4;
  for (int iteration = 0; iteration < 60 && std::isfinite(cost); ++iteration) {
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n, n);
    Eigen::VectorXd g = Eigen::VectorXd::Zero(n);
    for (const RaySample& s : samples) {
      Eigen::Vector2d px;
      CameraModel::IntrinsicsJacobian J(2, n);
      if (!model->project(s.ray, &px) || !model->intrinsicsJacobian(s.ray, &J)) continue;
      H.noalias() += J.transpose() * J;
      g.noalias() += J.transpose() * (px - s.pixel);
    }
    bool improved = false;
    while (lambda < 1e12) {
      Eigen::MatrixXd A = H;
      A.diagonal() += lambda * H.diagonal().cwiseMax(1e-12);
      const Eigen::VectorXd delta = A.ldlt().solve(-g);
      std::unique_ptr<CameraModel> candidate;
      try {
        candidate = model->withParameters(model->parameters() + delta);
      } catch (const InputError&) {
        lambda *= 10.0;
        continue;
      }
      const double c = fitCost(*candidate, samples);
      if (c < cost) {
        const bool converged = cost - c <= 1e-14 * cost;
        model = std::move(candidate);
        cost = c;
        lambda = std::max(lambda * 0.1, 1e-12);
        improved = !converged;
        break;
      }
      lambda *= 10.0;
    }
    if (!improved) break;
  }
  return model;
}

/// Standard deviation of `value` over the newest kSpreadWindows samples of `history`.
template <typename Value>
double spread(const std::vector<CalibrationSample>& history, Value value) {
  const size_t n = std::min<size_t>(history.size(), kSpreadWindows);
  if (n < 2) return 0.0;
  double mean = 0.0, sq = 0.0;
  for (size_t i = history.size() - n; i < history.size(); ++i) mean += value(history[i]);
  mean /= static_cast<double>(n);
  for (size_t i = history.size() - n; i < history.size(); ++i)
    sq += (value(history[i]) - mean) * (value(history[i]) - mean);
  return std::sqrt(sq / static_cast<double>(n - 1));
}

std::string commentLines(const RefinedCameraFit& fit, const std::string& source,
                         const char* prefix) {
  char buf[512];
  std::string s;
  std::snprintf(buf, sizeof(buf), "%s camera refined online by ldsm from %s\n", prefix,
                source.c_str());
  s += buf;
  if (!fit.changed) {
    std::snprintf(buf, sizeof(buf),
                  "%s the refinement applied no correction: this is the given calibration\n",
                  prefix);
    s += buf;
  } else {
    std::snprintf(buf, sizeof(buf),
                  "%s input model refitted to the refined rays: rms %.4f px, max %.4f px over %d "
                  "pixels\n",
                  prefix, fit.rms_px, fit.max_px, fit.samples);
    s += buf;
  }
  std::snprintf(buf, sizeof(buf),
                "%s 1-sigma (formal) of the rectified pinhole: fx %.3g fy %.3g cx %.3g cy %.3g px, "
                "radial k %.3g (0: not refined)\n",
                prefix, fit.sigma_fx, fit.sigma_fy, fit.sigma_cx, fit.sigma_cy, fit.sigma_k);
  s += buf;
  std::snprintf(buf, sizeof(buf),
                "%s 1-sigma (realistic: formal x window overlap x the windows' observed scatter): "
                "fx %.3g fy %.3g cx %.3g cy %.3g px, radial k %.3g\n",
                prefix, fit.realistic_sigma_fx, fit.realistic_sigma_fy, fit.realistic_sigma_cx,
                fit.realistic_sigma_cy, fit.realistic_sigma_k);
  s += buf;
  if (fit.spread_windows > 1) {
    std::snprintf(buf, sizeof(buf),
                  "%s spread of the last %d window estimates: fx %.3g fy %.3g cx %.3g cy %.3g px, "
                  "radial k %.3g\n",
                  prefix, fit.spread_windows, fit.spread_fx, fit.spread_fy, fit.spread_cx,
                  fit.spread_cy, fit.spread_k);
    s += buf;
  }
  return s;
}

}  // namespace

RefinedCameraFit refitCalibration(const GeometricCalibration& given,
                                  const CalibrationStats& refined,
                                  const std::vector<CalibrationSample>& history) {
  const std::unique_ptr<CameraModel> input = makeCameraModel(given.input);
  const PinholeIntrinsics k0 = computeOutputIntrinsics(*input, given.output);
  if (!samePinhole(k0, refined.configured))
    throw InputError("refined calibration: the engine's configured pinhole (fx " +
                     std::to_string(refined.configured.fx) + ", " +
                     std::to_string(refined.configured.width) + "x" +
                     std::to_string(refined.configured.height) +
                     ") is not the output of the given calibration (fx " + std::to_string(k0.fx) +
                     ", " + std::to_string(k0.width) + "x" + std::to_string(k0.height) + ")");
  const PinholeIntrinsics& ka = refined.applied;
  const double k = refined.radial_applied;
  RefinedCameraFit fit;
  fit.calibration = given;
  fit.sigma_fx = ka.fx * refined.focal_scale_sigma;
  fit.sigma_fy = ka.fy * refined.focal_scale_sigma;
  fit.sigma_cx = refined.cx_sigma;
  fit.sigma_cy = refined.cy_sigma;
  fit.sigma_k = refined.radial_sigma;
  fit.realistic_sigma_fx = ka.fx * refined.realistic_focal_scale_sigma;
  fit.realistic_sigma_fy = ka.fy * refined.realistic_focal_scale_sigma;
  fit.realistic_sigma_cx = refined.realistic_cx_sigma;
  fit.realistic_sigma_cy = refined.realistic_cy_sigma;
  fit.realistic_sigma_k = refined.realistic_radial_sigma;
  fit.spread_windows = static_cast<int>(std::min<size_t>(history.size(), kSpreadWindows));
  fit.spread_fx = ka.fx * spread(history, [](const CalibrationSample& c) {
                    return std::log(c.focal_scale_estimate);
                  });
  fit.spread_fy = fit.spread_fx * ka.fy / ka.fx;
  fit.spread_cx = spread(history, [](const CalibrationSample& c) { return c.cx_shift_estimate; });
  fit.spread_cy = spread(history, [](const CalibrationSample& c) { return c.cy_shift_estimate; });
  fit.spread_k = spread(history, [](const CalibrationSample& c) { return c.radial_estimate; });
  if (samePinhole(ka, k0) && k == 0.0) return fit;
  fit.changed = true;

  const std::vector<RaySample> samples = refinedRays(*input, k0, ka, k);
  if (samples.size() < 16)
    throw InputError(
        "refined calibration: fewer than 16 pixels of the input image map into the "
        "refined camera");
  CameraIntrinsics start = given.input;
  if (start.model == CameraModelType::Pinhole && k != 0.0) {
    start.model = CameraModelType::RadTan;
    start.distortion.assign(4, 0.0);
  }
  const std::unique_ptr<CameraModel> model = fitModel(makeCameraModel(start), samples);
  fit.calibration.input = model->intrinsics();
  for (double& d : fit.calibration.input.distortion)
    if (std::abs(d) < 1e-12) d = 0.0;  // what the fit left of a term the rays do not have
  double sum = 0.0;
  for (const RaySample& s : samples) {
    Eigen::Vector2d px;
    if (!model->project(s.ray, &px)) continue;
    const double e = (px - s.pixel).norm();
    sum += e * e;
    fit.max_px = std::max(fit.max_px, e);
  }
  fit.samples = static_cast<int>(samples.size());
  fit.rms_px = std::sqrt(sum / static_cast<double>(samples.size()));
  if (given.output.mode == OutputMode::None && model->type() != CameraModelType::Pinhole) {
    // A distorted input cannot keep output mode none: keep the engine's refined pinhole.
    RectificationSpec& out = fit.calibration.output;
    out.mode = OutputMode::Explicit;
    out.relative = false;
    out.fx = ka.fx;
    out.fy = ka.fy;
    out.cx = ka.cx;
    out.cy = ka.cy;
    out.width = ka.width;
    out.height = ka.height;
  }
  return fit;
}

std::string formatRefinedDsoCameraFile(const RefinedCameraFit& fit, const std::string& source) {
  return commentLines(fit, source, "#") + formatDsoCameraFile(fit.calibration);
}

std::string formatRefinedKalibrYaml(const RefinedCameraFit& fit, const std::string& source) {
  return commentLines(fit, source, "#") + formatKalibrCameraYaml(fit.calibration);
}

}  // namespace ldsm::calib
