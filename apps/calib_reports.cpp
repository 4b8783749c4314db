#include "calib_reports.h"

#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdio>

#include "ldsm/camera/camera_model.h"

namespace ldsm::app {
namespace {

/// `v` with `decimals` decimals, "-" when it is not a number.
std::string number(double v, int decimals) {
  if (!std::isfinite(v)) return "-";
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
  return buf;
}

void warnAll(const std::vector<std::string>& warnings) {
  for (const auto& w : warnings) spdlog::warn("{}", w);
}

}  // namespace

std::string cameraReportText(const std::string& source, const calib::BoardSpec& spec,
                             const std::string& model, const calib::CameraCalibrationResult& r) {
  std::string s = "# ldsm calib camera: " + source + ", " + calib::toString(spec.type) + " " +
                  std::to_string(spec.cols) + "x" + std::to_string(spec.rows) + " squares, model " +
                  model + "\n# image status corners blur_px rms_px reason\n";
  char line[512];
  for (const auto& v : r.views) {
    std::snprintf(line, sizeof(line), "%s %s %d %.3f %.3f %s\n", v.name.c_str(),
                  calib::toString(v.status), v.corners, v.blur_px, v.rms_px, v.reason.c_str());
    s += line;
  }
  std::snprintf(line, sizeof(line), "# used %d of %zu views, reprojection RMS %.4f px\n",
                r.used_views, r.views.size(), r.rms_px);
  return s + line;
}

void printCameraSummary(const calib::CameraCalibrationResult& r, const std::string& written) {
  std::printf("%-24s %-9s %7s %8s %8s\n", "view", "status", "corners", "blur px", "RMS px");
  for (const auto& v : r.views)
    std::printf("%-24s %-9s %7d %8s %8s%s%s\n", v.name.c_str(), calib::toString(v.status),
                v.corners, number(v.blur_px, 2).c_str(), number(v.rms_px, 3).c_str(),
                v.reason.empty() ? "" : "  ", v.reason.c_str());
  const CameraIntrinsics& k = r.calibration.input;
  std::printf("\nviews:        %d used of %zu\n", r.used_views, r.views.size());
  std::printf("model:        %s fx %.3f fy %.3f cx %.3f cy %.3f", cameraModelName(k.model), k.fx,
              k.fy, k.cx, k.cy);
  for (const double d : k.distortion) std::printf(" %.5f", d);
  std::printf("\nreprojection: RMS %.3f px over %zu corners\n", r.rms_px, r.corners.size());
  std::printf("written:      %s\n", written.c_str());
  warnAll(r.warnings);
}

void printResponseSummary(const calib::ResponseCalibrationResult& r, std::size_t images,
                          const std::array<float, 256>* reference, const std::string& written) {
  std::printf(
      "images:       %d used of %zu (skipped: %zu almost all saturated, %zu almost all "
      "dark)\n",
      r.images_used, images, r.skipped_saturated.size(), r.skipped_dark.size());
  std::printf("values:       %d..%d observed (outside: extrapolated)\n", r.first_observed,
              r.last_observed);
  const std::string decreasing =
      std::to_string(r.non_monotonic.size()) + " values decrease (see response.png)";
  std::printf("monotonic:    %s\n", r.non_monotonic.empty() ? "yes" : decreasing.c_str());
  std::printf(
      "residual:     %.3f (RMS of G^-1(I) - t B), noise sigma %.2f grey levels, %d "
      "iterations\n",
      r.rms_residual, r.noise_sigma, r.iterations);
  if (reference) {
    const double scale = 255.0 / (*reference)[255];
    double s = 0;
    for (std::size_t k = 0; k < 256; ++k) {
      const double d = r.inverse_response[k] - scale * (*reference)[k];
      s += d * d;
    }
    std::printf("reference:    RMS difference %.3f (%.2f %% of the range)\n", std::sqrt(s / 256),
                100.0 * std::sqrt(s / 256) / 255.0);
  }
  std::printf("written:      %s\n", written.c_str());
  warnAll(r.warnings);
}

void printVignetteSummary(const calib::VignetteCalibrationResult& r, std::size_t images,
                          const std::string& written) {
  std::printf("images:       %d used of %zu (%dx%d)\n", r.images_used, images, r.vignette.width(),
              r.vignette.height());
  std::printf("centre:       (%.2f, %.2f) px\n", r.centre.x(), r.centre.y());
  std::printf("model:        V = %.4f (1 %+.4f r^2 %+.4f r^4 %+.4f r^6), r = distance / %.1f px\n",
              r.scale, r.coefficients[0], r.coefficients[1], r.coefficients[2], r.radius_px);
  std::printf("minimum:      %.3f\n", r.min_value);
  std::printf("fit residual: %.2f %% RMS, %.1f %% of the image down-weighted\n", 100 * r.fit_rms,
              100 * r.outlier_fraction);
  std::printf("written:      %s\n", written.c_str());
  warnAll(r.warnings);
}

}  // namespace ldsm::app
