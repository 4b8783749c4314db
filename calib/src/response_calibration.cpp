#include "ldsm/calib/response_calibration.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "ldsm/error.h"
#include "response_solver.h"
#include "sweep_samples.h"

namespace ldsm::calib {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string fmt(double v, int decimals = 2) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
  return buf;
}

void validate(const ResponseCalibrationOptions& o) {
  if (o.min_value < 1 || o.max_value > 254 || o.max_value - o.min_value < 64)
    throw ConfigError(
        "response calibration: need 1 <= min_value, max_value <= 254 and at least "
        "64 values between them");
  if (o.max_iterations < 1 || !(o.tolerance > 0) || o.max_pixels < 1000 ||
      !(o.min_exposure_range >= 1) || !(o.min_usable_fraction >= 0) ||
      !(o.max_exposure_deviation > 0))
    throw ConfigError("response calibration: invalid options");
}

/// Least-squares line (or parabola, degree 2) through (x, y) with weights, evaluated at x0.
double extrapolate(const std::vector<double>& x, const std::vector<double>& y,
                   const std::vector<double>& w, int degree, double x0) {
  // Normal equations in the centred variable for conditioning.
  const double xc = std::accumulate(x.begin(), x.end(), 0.0) / static_cast<double>(x.size());
  double A[3][3] = {}, b[3] = {};
  const int n = degree + 1;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double d = x[i] - xc;
    const double p[3] = {1.0, d, d * d};
    for (int r = 0; r < n; ++r) {
      b[r] += w[i] * p[r] * y[i];
      for (int c = 0; c < n; ++c) A[r][c] += w[i] * p[r] * p[c];
    }
  }
  // Gaussian elimination (n <= 3, well conditioned after centring).
  for (int c = 0; c < n; ++c) {
    int piv = c;
    for (int r = c + 1; r < n; ++r)
      if (std::abs(A[r][c]) > std::abs(A[piv][c])) piv = r;
    std::swap(A[c], A[piv]);
    std::swap(b[c], b[piv]);
    if (std::abs(A[c][c]) < 1e-12) return kNaN;
    for (int r = c + 1; r < n; ++r) {
      const double f = A[r][c] / A[c][c];
      for (int k = c; k < n; ++k) A[r][k] -= f * A[c][k];
      b[r] -= f * b[c];
    }
  }
  double coef[3] = {};
  for (int r = n - 1; r >= 0; --r) {
    double s = b[r];
    for (int k = r + 1; k < n; ++k) s -= A[r][k] * coef[k];
    coef[r] = s / A[r][r];
  }
  const double d = x0 - xc;
  return coef[0] + coef[1] * d + (degree > 1 ? coef[2] * d * d : 0.0);
}

/// Fills the values without an estimate: linear between estimates, extrapolated at both ends
/// (a line through the first 8 estimates, a parabola through the last 16), kept non-decreasing.
std::array<double, 256> completeCurve(const std::vector<double>& fitted,
                                      const std::array<std::int64_t, 256>& counts, int first,
                                      int last) {
  std::array<double, 256> u{};
  std::vector<int> known;
  for (int v = first; v <= last; ++v)
    if (counts[static_cast<std::size_t>(v)] >= detail::kMinResponseCount) known.push_back(v);
  for (std::size_t j = 0; j + 1 < known.size(); ++j) {
    const int a = known[j], b = known[j + 1];
    for (int v = a; v <= b; ++v)
      u[static_cast<std::size_t>(v)] =
          fitted[static_cast<std::size_t>(a)] +
          (fitted[static_cast<std::size_t>(b)] - fitted[static_cast<std::size_t>(a)]) * (v - a) /
              static_cast<double>(b - a);
  }
  auto endFit = [&](bool top, int count, int degree, int at) {
    std::vector<double> x, y, w;
    const std::size_t n = std::min<std::size_t>(known.size(), static_cast<std::size_t>(count));
    for (std::size_t j = 0; j < n; ++j) {
      const int v = top ? known[known.size() - 1 - j] : known[j];
      x.push_back(v);
      y.push_back(fitted[static_cast<std::size_t>(v)]);
      w.push_back(std::sqrt(static_cast<double>(counts[static_cast<std::size_t>(v)])));
    }
    return extrapolate(x, y, w, degree, at);
  };
  for (int v = first - 1; v >= 0; --v) {
    const double e = endFit(false, 8, 1, v);
    u[static_cast<std::size_t>(v)] =
        std::clamp(std::isfinite(e) ? e : 0.0, 0.0, u[static_cast<std::size_t>(v + 1)]);
  }
  // Slope at the top end, so that a parabola bending over is not followed.
  const double slope = last > first ? (u[static_cast<std::size_t>(last)] -
                                       u[static_cast<std::size_t>(std::max(first, last - 8))]) /
                                          (last - std::max(first, last - 8))
                                    : 0.0;
  for (int v = last + 1; v < 256; ++v) {
    const double e = endFit(true, 16, 2, v);
    const double prev = u[static_cast<std::size_t>(v - 1)];
    const double linear = prev + std::max(slope, 0.0);
    u[static_cast<std::size_t>(v)] = std::isfinite(e) && e > prev ? std::max(e, linear) : linear;
  }
  return u;
}

}  // namespace

std::vector<double> monotoneFit(const std::vector<double>& values,
                                const std::vector<double>& weights) {
  struct Block {
    double mean, weight;
    std::size_t first, last;
  };
  std::vector<Block> blocks;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!(weights[i] > 0)) continue;
    blocks.push_back({values[i], weights[i], i, i});
    while (blocks.size() > 1 && blocks[blocks.size() - 2].mean > blocks.back().mean) {
      const Block b = blocks.back();
      blocks.pop_back();
      Block& a = blocks.back();
      a.mean = (a.mean * a.weight + b.mean * b.weight) / (a.weight + b.weight);
      a.weight += b.weight;
      a.last = b.last;
    }
  }
  std::vector<double> out = values;
  for (const Block& b : blocks)
    for (std::size_t i = b.first; i <= b.last; ++i)
      if (weights[i] > 0) out[i] = b.mean;
  return out;
}

ResponseCalibrationResult calibrateResponse(const std::vector<ExposedImage>& images,
                                            const ResponseCalibrationOptions& options,
                                            const std::string& source) {
  validate(options);
  detail::SweepSamples sweep(images, options.min_value, options.max_value, options.max_pixels,
                             options.min_usable_fraction, source);
  ResponseCalibrationResult result;
  result.images_used = sweep.imageCount();
  result.skipped_saturated = sweep.saturatedImages();
  result.skipped_dark = sweep.darkImages();

  const double range = sweep.exposureRange();
  if (range < options.min_exposure_range) {
    std::string hint;
    if (sweep.saturatedFraction() > 0.5)
      hint = "; the images are mostly saturated (" + fmt(100 * sweep.saturatedFraction(), 0) +
             "% of the pixels): use shorter exposures";
    else if (sweep.darkFraction() > 0.5)
      hint = "; the images are mostly dark (" + fmt(100 * sweep.darkFraction(), 0) +
             "% of the pixels): use longer exposures";
    throw InputError(source + ": the usable exposure times span only " + fmt(range) + "x (" +
                     fmt(sweep.exposure(0), 3) + " to " +
                     fmt(sweep.exposure(sweep.imageCount() - 1), 3) + " ms)" + hint +
                     "; record the sweep from nearly black to nearly white images, at least " +
                     fmt(options.min_exposure_range, 0) +
                     "x apart (e.g. doubling the exposure time 8-12 times)");
  }

  const std::string inconsistency = sweep.brightnessCheck();
  if (!inconsistency.empty()) {
    if (!options.allow_inconsistent) throw InputError(source + ": " + inconsistency);
    result.warnings.push_back(inconsistency);
  }

  // Alternating least squares from a linear response; then, a few times, the samples the fit
  // cannot explain are dropped and the fit repeated.
  detail::ResponseSolver solver(sweep);
  result.iterations = solver.solve(options.max_iterations, options.tolerance);
  std::array<double, 256> curve{};
  for (int round = 0;; ++round) {
    const auto& U = solver.inverseResponse();
    const auto& count = solver.counts();
    result.first_observed = -1;
    for (std::size_t k = 0; k < 256; ++k) {
      result.counts[k] = count[k];
      result.estimate[k] = count[k] >= detail::kMinResponseCount ? U[k] : kNaN;
      if (count[k] >= detail::kMinResponseCount) {
        if (result.first_observed < 0) result.first_observed = static_cast<int>(k);
        result.last_observed = static_cast<int>(k);
      }
    }
    if (result.first_observed < 0 || result.last_observed - result.first_observed < 64)
      throw InputError(source + ": the pixel values span only " +
                       std::to_string(std::max(result.first_observed, 0)) + ".." +
                       std::to_string(result.last_observed) +
                       "; film a scene with dark and bright parts and sweep the exposure from "
                       "nearly black to nearly white images");
    // Closest non-decreasing curve, completed outside the observed range.
    std::vector<double> values(256, 0.0), weights(256, 0.0);
    for (std::size_t k = 0; k < 256; ++k)
      if (count[k] >= detail::kMinResponseCount) {
        values[k] = U[k];
        weights[k] = static_cast<double>(count[k]);
      }
    curve = completeCurve(monotoneFit(values, weights), result.counts, result.first_observed,
                          result.last_observed);
    if (round == 4) break;
    std::size_t dropped = solver.rejectOutliers(curve, 4.0, 2.0);
    if (round == 0) {
      // With more noise, clipped values reach further into the range: keep 3 sigma away from
      // both ends.
      const int margin = static_cast<int>(std::ceil(3.0 * solver.noiseSigma()));
      const int lo = std::max(options.min_value, margin + 1);
      const int hi = std::min(options.max_value, 254 - margin);
      if (lo > options.min_value || hi < options.max_value) {
        dropped += solver.restrictValues(lo, hi);
        result.warnings.push_back("the noise (sigma " + fmt(solver.noiseSigma()) +
                                  " grey levels) limits the usable pixel values to " +
                                  std::to_string(lo) + ".." + std::to_string(hi));
      }
    }
    if (dropped == 0) break;
    result.iterations += solver.solve(options.max_iterations, options.tolerance);
  }
  result.noise_sigma = solver.noiseSigma();
  double previous = kNaN;
  for (int k = result.first_observed; k <= result.last_observed; ++k) {
    const double e = result.estimate[static_cast<std::size_t>(k)];
    if (std::isnan(e)) continue;
    if (e < previous) result.non_monotonic.push_back(k);
    previous = e;
  }
  // DSO's scale: G^-1(255) = 255.
  const double to255 = 255.0 / curve[255];
  for (std::size_t k = 0; k < 256; ++k) {
    result.inverse_response[k] = static_cast<float>(curve[k] * to255);
    result.estimate[k] *= to255;
  }
  result.inverse_response[255] = 255.0f;

  // Residual and the exposure each image appears to have.
  const int n_images = sweep.imageCount();
  const std::size_t n_pixels = sweep.pixelCount();
  const auto& U = solver.inverseResponse();
  const auto& B = solver.irradiance();
  double res2 = 0.0;
  std::int64_t n_res = 0;
  result.exposure_scale.assign(images.size(), kNaN);
  // The apparent exposure uses the samples whose fitted value t B is mid-range (selecting them by
  // their observed value would bias the mean by the noise near the limits of the range).
  const double mid_lo = U[static_cast<std::size_t>(std::max(result.first_observed, 24))];
  const double mid_hi = U[static_cast<std::size_t>(std::min(result.last_observed, 230))];
  int off_images = 0;
  double worst_scale = 1.0;
  std::string worst_name;
  for (int i = 0; i < n_images; ++i) {
    const double t = sweep.exposure(i);
    double ub = 0.0, bb = 0.0;
    int n_mid = 0;
    for (std::size_t x = 0; x < n_pixels; ++x) {
      if (!solver.used(i, x) || std::isnan(B[x])) continue;
      const int v = sweep.value(i, x);
      const double u = U[static_cast<std::size_t>(v)];
      const double r = (u - t * B[x]) * to255;
      res2 += r * r;
      ++n_res;
      if (t * B[x] < mid_lo || t * B[x] > mid_hi) continue;
      ub += u * B[x];
      bb += B[x] * B[x];
      ++n_mid;
    }
    const double s = n_mid >= 50 ? ub / (t * bb) : kNaN;
    result.exposure_scale[sweep.inputIndex(i)] = s;
    if (std::isfinite(s) && std::abs(s - 1.0) > options.max_exposure_deviation) {
      ++off_images;
      if (std::abs(s - 1.0) > std::abs(worst_scale - 1.0)) {
        worst_scale = s;
        worst_name = sweep.name(i);
      }
    }
  }
  if (off_images > 0)
    result.warnings.push_back(
        std::to_string(off_images) +
        " images do not have the brightness their exposure time "
        "predicts (by more than " +
        fmt(100 * options.max_exposure_deviation, 0) + "%; worst: " + worst_name + ", " +
        fmt(100 * std::abs(worst_scale - 1.0), 0) + "% " +
        (worst_scale > 1 ? "brighter" : "darker") +
        "); check the exposure times and that gain and lighting stayed constant");
  result.rms_residual = n_res > 0 ? std::sqrt(res2 / static_cast<double>(n_res)) : 0.0;

  if (!result.non_monotonic.empty()) {
    double drop = 0.0;
    int at = result.non_monotonic.front();
    double prev = kNaN;
    for (int k = result.first_observed; k <= result.last_observed; ++k) {
      const double e = result.estimate[static_cast<std::size_t>(k)];
      if (std::isnan(e)) continue;
      if (e < prev && prev - e > drop) {
        drop = prev - e;
        at = k;
      }
      prev = e;
    }
    if (drop > 0.5)
      result.warnings.push_back(
          "the estimated G^-1 decreases at " + std::to_string(result.non_monotonic.size()) +
          " pixel values (largest drop " + fmt(drop) + " at " + std::to_string(at) +
          "); the written curve is its closest non-decreasing fit. Large drops mean "
          "auto-exposure or auto-gain was on, or the scene or light changed");
  }
  if (result.first_observed > 24)
    result.warnings.push_back("no pixel values below " + std::to_string(result.first_observed) +
                              " were usable: G^-1 below is extrapolated; add shorter exposures");
  if (result.last_observed < 230)
    result.warnings.push_back("no pixel values above " + std::to_string(result.last_observed) +
                              " were usable: G^-1 above is extrapolated; add longer exposures");
  return result;
}

}  // namespace ldsm::calib
