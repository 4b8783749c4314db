#include "ldsm/calib/vignette_calibration.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "ldsm/error.h"

namespace ldsm::calib {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kMinVignette = 0.01;

std::string fmt(double v, int decimals = 2) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
  return buf;
}

/// The block averages the model is fitted to.
struct Samples {
  std::vector<Eigen::Vector2d> xy;
  std::vector<double> value, weight;
};

/// Model s + p1 r^2 + p2 r^4 + p3 r^6 with r^2 = |x - c|^2 / R^2; params (s, p1, p2, p3, cx, cy).
struct RadialModel {
  Eigen::Matrix<double, 6, 1> p;
  double inv_r2 = 1.0;  // 1 / R^2

  double value(const Eigen::Vector2d& x) const {
    const double r2 = (x - p.tail<2>()).squaredNorm() * inv_r2;
    return p(0) + r2 * (p(1) + r2 * (p(2) + r2 * p(3)));
  }
  Eigen::Matrix<double, 1, 6> jacobian(const Eigen::Vector2d& x) const {
    const Eigen::Vector2d d = x - p.tail<2>();
    const double r2 = d.squaredNorm() * inv_r2;
    const double dm_dr2 = p(1) + r2 * (2 * p(2) + 3 * r2 * p(3));
    Eigen::Matrix<double, 1, 6> J;
    J << 1.0, r2, r2 * r2, r2 * r2 * r2, dm_dr2 * (-2.0 * d.x() * inv_r2),
        dm_dr2 * (-2.0 * d.y() * inv_r2);
    return J;
  }
};

double medianOf(std::vector<double> v) {
  if (v.empty()) return kNaN;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

/// Robust scale of the relative residuals (1.4826 MAD), at least 1e-4.
double robustSigma(const RadialModel& m, const Samples& s) {
  std::vector<double> r;
  for (std::size_t i = 0; i < s.xy.size(); ++i) {
    const double v = m.value(s.xy[i]);
    r.push_back(std::abs(s.value[i] - v) / std::max(std::abs(v), 1e-6));
  }
  return std::max(1.4826 * medianOf(r), 1e-4);
}

/// Weighted Gauss-Newton / Levenberg-Marquardt with Huber weights re-computed every iteration.
/// Only the first `n` parameters are estimated (4: centre fixed, 6: centre fitted).
void fitModel(RadialModel& m, const Samples& s, int n, double huber_k) {
  double lambda = 1e-3;
  for (int iter = 0; iter < 60; ++iter) {
    const double sigma = robustSigma(m, s);
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n, n);
    Eigen::VectorXd g = Eigen::VectorXd::Zero(n);
    double cost = 0.0;
    std::vector<double> w(s.xy.size());
    for (std::size_t i = 0; i < s.xy.size(); ++i) {
      const double v = m.value(s.xy[i]);
      const double r = s.value[i] - v;
      const double rel = std::abs(r) / std::max(std::abs(v), 1e-6) / sigma;
      w[i] = s.weight[i] * (rel <= huber_k ? 1.0 : huber_k / rel);
      const Eigen::VectorXd J = m.jacobian(s.xy[i]).head(n).transpose();
      H += w[i] * J * J.transpose();
      g += w[i] * J * r;
      cost += w[i] * r * r;
    }
    bool improved = false;
    for (int tries = 0; tries < 10 && !improved; ++tries) {
      Eigen::MatrixXd A = H;
      A.diagonal() *= 1.0 + lambda;
      const Eigen::VectorXd step = A.ldlt().solve(g);
      RadialModel trial = m;
      trial.p.head(n) += step;
      double trial_cost = 0.0;
      for (std::size_t i = 0; i < s.xy.size(); ++i) {
        const double r = s.value[i] - trial.value(s.xy[i]);
        trial_cost += w[i] * r * r;
      }
      if (trial_cost <= cost) {
        const double rel_step = step.head(std::min(n, 4)).norm() / std::max(std::abs(m.p(0)), 1e-9);
        const double centre_step = n > 4 ? step.tail(2).norm() : 0.0;
        m = trial;
        lambda = std::max(lambda * 0.3, 1e-9);
        improved = true;
        if (rel_step < 1e-9 && centre_step < 1e-4) return;
      } else {
        lambda *= 10.0;
      }
    }
    if (!improved) return;
  }
}

void validateInputs(const std::vector<ExposedImage>& images,
                    const std::array<float, 256>& inverse_response,
                    const VignetteCalibrationOptions& options, const std::string& source) {
  if (options.min_value < 0 || options.max_value > 255 || options.min_value >= options.max_value ||
      options.block < 1 || !(options.huber_k > 0) || !(options.max_fit_rms > 0))
    throw ConfigError("vignette calibration: invalid options");
  if (images.empty()) throw InputError(source + ": no images of the flat surface");
  const int W = images.front().image.width, H = images.front().image.height;
  for (const ExposedImage& im : images) {
    if (im.image.empty()) throw InputError(source + ": " + im.name + ": empty image");
    if (im.image.width != W || im.image.height != H)
      throw InputError(source + ": " + im.name + " is " + std::to_string(im.image.width) + "x" +
                       std::to_string(im.image.height) + " but " + images.front().name + " is " +
                       std::to_string(W) + "x" + std::to_string(H));
    if (!(std::isfinite(im.exposure_ms) && im.exposure_ms > 0.0))
      throw InputError(source + ": " + im.name + " has exposure time " + fmt(im.exposure_ms, 4) +
                       " ms; every image needs a positive exposure time (the third column of "
                       "times.txt, in milliseconds)");
  }
  for (std::size_t k = 0; k < 256; ++k)
    if (!std::isfinite(inverse_response[k]) ||
        (k > 0 && inverse_response[k] < inverse_response[k - 1]))
      throw InputError(source + ": the inverse response is not finite and non-decreasing at " +
                       std::to_string(k));
  if (!(inverse_response[255] > inverse_response[0]))
    throw InputError(source + ": the inverse response is constant");
}

}  // namespace

VignetteCalibrationResult calibrateVignette(const std::vector<ExposedImage>& images,
                                            const std::array<float, 256>& inverse_response,
                                            const VignetteCalibrationOptions& options,
                                            const std::string& source) {
  validateInputs(images, inverse_response, options, source);
  const int W = images.front().image.width, H = images.front().image.height;
  VignetteCalibrationResult result;

  // Average of the median-normalised irradiance images.
  std::vector<double> sum(static_cast<std::size_t>(W) * H, 0.0);
  std::vector<int> count(sum.size(), 0);
  int too_dark = 0, too_bright = 0;
  std::vector<double> e;
  for (const ExposedImage& im : images) {
    e.clear();
    int dark = 0, bright = 0;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        const int v = im.image(x, y);
        dark += v < options.min_value;
        bright += v > options.max_value;
        if (v >= options.min_value && v <= options.max_value)
          e.push_back(inverse_response[static_cast<std::size_t>(v)] / im.exposure_ms);
      }
    if (e.size() < sum.size() / 5) {
      ++(dark > bright ? too_dark : too_bright);
      result.warnings.push_back("skipped " + im.name + ": fewer than 20% of its pixels are in " +
                                std::to_string(options.min_value) + ".." +
                                std::to_string(options.max_value));
      continue;
    }
    const double med = medianOf(e);
    if (!(med > 0)) continue;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        const int v = im.image(x, y);
        if (v < options.min_value || v > options.max_value) continue;
        const std::size_t i = static_cast<std::size_t>(y) * W + x;
        sum[i] += inverse_response[static_cast<std::size_t>(v)] / im.exposure_ms / med;
        ++count[i];
      }
    ++result.images_used;
  }
  if (result.images_used == 0)
    throw InputError(source + ": no image has enough usable pixels (" + std::to_string(too_dark) +
                     " too dark, " + std::to_string(too_bright) +
                     " saturated); expose the flat surface so that its centre is bright but below "
                     "saturation (about 200 of 255)");

  // Block averages.
  Samples s;
  const int B = options.block;
  int blocks = 0;
  for (int by = 0; by < H; by += B)
    for (int bx = 0; bx < W; bx += B) {
      ++blocks;
      double v = 0.0, n = 0.0, cx = 0.0, cy = 0.0;
      int pixels = 0;
      for (int y = by; y < std::min(by + B, H); ++y)
        for (int x = bx; x < std::min(bx + B, W); ++x) {
          ++pixels;
          const std::size_t i = static_cast<std::size_t>(y) * W + x;
          if (count[i] == 0) continue;
          const double m = sum[i] / count[i];
          v += count[i] * m;
          n += count[i];
          cx += count[i] * x;
          cy += count[i] * y;
        }
      if (n < 0.5 * pixels) continue;
      s.xy.emplace_back(cx / n, cy / n);
      s.value.push_back(v / n);
      s.weight.push_back(n);
    }
  if (s.xy.size() < 30 || static_cast<double>(s.xy.size()) < 0.5 * blocks)
    throw InputError(source + ": the usable pixels cover only " +
                     fmt(100.0 * static_cast<double>(s.xy.size()) / blocks, 0) +
                     "% of the image; the flat surface must fill the image, evenly lit, neither "
                     "saturated nor too dark");

  // Fit: linear coefficients with the centre at its start, then everything.
  RadialModel m;
  result.radius_px = 0.5 * std::hypot(W, H);
  m.inv_r2 = 1.0 / (result.radius_px * result.radius_px);
  const Eigen::Vector2d start =
      options.centre.value_or(Eigen::Vector2d(0.5 * (W - 1), 0.5 * (H - 1)));
  m.p << 1.0, 0.0, 0.0, 0.0, start.x(), start.y();
  fitModel(m, s, 4, options.huber_k);
  if (!options.centre) fitModel(m, s, 6, options.huber_k);

  // Scale to a maximum of 1 over the image; the measured average likewise.
  result.vignette.resize(W, H);
  result.measured.resize(W, H);
  double vmax = 0.0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) vmax = std::max(vmax, m.value(Eigen::Vector2d(x, y)));
  if (!(vmax > 0))
    throw InputError(source +
                     ": the vignette fit failed (no positive value); check that the "
                     "images show an evenly lit flat surface");
  double vmin = 1.0;
  bool clamped = false;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      double v = m.value(Eigen::Vector2d(x, y)) / vmax;
      if (v < kMinVignette) {
        v = kMinVignette;
        clamped = true;
      }
      vmin = std::min(vmin, v);
      result.vignette(x, y) = static_cast<float>(v);
      const std::size_t i = static_cast<std::size_t>(y) * W + x;
      result.measured(x, y) = static_cast<float>(count[i] ? sum[i] / count[i] / vmax : kNaN);
    }
  result.centre = m.p.tail<2>();
  result.scale = m.p(0) / vmax;
  for (int k = 0; k < 3; ++k)
    result.coefficients[static_cast<std::size_t>(k)] = m.p(k + 1) / m.p(0);
  result.min_value = vmin;

  // Fit quality over the inliers.
  const double sigma = robustSigma(m, s);
  double r2 = 0.0, wsum = 0.0;
  int outliers = 0;
  for (std::size_t i = 0; i < s.xy.size(); ++i) {
    const double v = m.value(s.xy[i]);
    const double rel = (s.value[i] - v) / v;
    if (std::abs(rel) > options.huber_k * sigma) {
      ++outliers;
      continue;
    }
    r2 += s.weight[i] * rel * rel;
    wsum += s.weight[i];
  }
  result.fit_rms = wsum > 0 ? std::sqrt(r2 / wsum) : kNaN;
  result.outlier_fraction = static_cast<double>(outliers) / static_cast<double>(s.xy.size());

  if (clamped)
    result.warnings.push_back("the fitted vignette falls below " + fmt(kMinVignette) +
                              " in the image corners; it is clamped there");
  if (result.fit_rms > options.max_fit_rms)
    result.warnings.push_back("the images deviate from a smooth radial vignette by " +
                              fmt(100 * result.fit_rms, 1) +
                              "% RMS: the surface must be flat, uniformly coloured and evenly lit, "
                              "and fill the whole image");
  if (result.outlier_fraction > 0.1)
    result.warnings.push_back(fmt(100 * result.outlier_fraction, 0) +
                              "% of the image does not fit the vignette (spots, reflections, "
                              "shadows?); they were down-weighted");
  const double off = (result.centre - Eigen::Vector2d(0.5 * (W - 1), 0.5 * (H - 1))).norm();
  if (!options.centre && off > 0.1 * 2 * result.radius_px)
    result.warnings.push_back("the fitted vignette centre is " + fmt(off, 0) +
                              " px from the image centre; uneven lighting can cause that: light "
                              "the surface evenly or give the centre");
  return result;
}

}  // namespace ldsm::calib
