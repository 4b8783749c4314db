#include "ldsm/camera/photometric_model.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "ldsm/error.h"

namespace ldsm {
namespace {

std::string fmt(double v) {
  std::ostringstream s;
  s.precision(9);
  s << v;
  return s.str();
}

}  // namespace

void validatePhotometricCalibration(const PhotometricCalibration& calibration, int width,
                                    int height) {
  if (calibration.has_response) {
    const auto& g = calibration.inverse_response;
    for (std::size_t i = 0; i < g.size(); ++i) {
      if (!std::isfinite(g[i]))
        throw InputError("photometric calibration: inverse response value " + std::to_string(i) +
                         " is not finite (" + fmt(g[i]) + ")");
      if (i > 0 && g[i] < g[i - 1])
        throw InputError("photometric calibration: inverse response decreases at index " +
                         std::to_string(i) + " (" + fmt(g[i]) + " < " + fmt(g[i - 1]) +
                         "); it must be non-decreasing");
    }
    if (!(g[255] > g[0]))
      throw InputError("photometric calibration: inverse response is constant (" + fmt(g[0]) + ")");
  }
  const ImageF& v = calibration.vignette;
  if (!v.empty()) {
    if (v.width() != width || v.height() != height)
      throw InputError("photometric calibration: vignette is " + std::to_string(v.width()) + "x" +
                       std::to_string(v.height()) + " but the images are " + std::to_string(width) +
                       "x" + std::to_string(height));
    for (int y = 0; y < v.height(); ++y)
      for (int x = 0; x < v.width(); ++x)
        if (!(v(x, y) > 0.0f && v(x, y) <= 1.0f))
          throw InputError("photometric calibration: vignette value at (" + std::to_string(x) +
                           ", " + std::to_string(y) + ") is " + fmt(v(x, y)) +
                           ", must be in (0, 1]");
  }
}

PhotometricModel::PhotometricModel(const PhotometricCalibration& calibration, int width, int height)
    : width_(width), height_(height) {
  if (width <= 0 || height <= 0)
    throw InputError("photometric calibration: image size must be positive (got " +
                     std::to_string(width) + "x" + std::to_string(height) + ")");
  validatePhotometricCalibration(calibration, width, height);
  if (calibration.has_response) {
    const auto& g = calibration.inverse_response;
    const double lo = g[0], scale = 255.0 / (static_cast<double>(g[255]) - lo);
    for (int i = 0; i < 256; ++i) inverse_response_[i] = static_cast<float>((g[i] - lo) * scale);
  } else {
    for (int i = 0; i < 256; ++i) inverse_response_[i] = static_cast<float>(i);
  }
  if (!calibration.vignette.empty()) {
    vignette_ = calibration.vignette;
    inverse_vignette_.resize(width, height);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) inverse_vignette_(x, y) = 1.0f / vignette_(x, y);
  }
}

void PhotometricModel::checkArguments(int width, int height, float exposure,
                                      const char* what) const {
  if (width != width_ || height != height_)
    throw InputError(std::string("photometric ") + what + ": image is " + std::to_string(width) +
                     "x" + std::to_string(height) + " but the calibration is for " +
                     std::to_string(width_) + "x" + std::to_string(height_));
  if (!(std::isfinite(exposure) && exposure > 0.0f))
    throw InputError(std::string("photometric ") + what +
                     ": exposure must be finite and positive (got " + fmt(exposure) + ")");
}

void PhotometricModel::correct(ImageView<const std::uint8_t> in, ImageF& out,
                               float exposure) const {
  checkArguments(in.width, in.height, exposure, "correction");
  out.resize(width_, height_);
  const float inv_t = 1.0f / exposure;
  for (int y = 0; y < height_; ++y) {
    const std::uint8_t* src = in.row(y);
    float* dst = out.row(y);
    if (inverse_vignette_.empty()) {
      for (int x = 0; x < width_; ++x) dst[x] = inverse_response_[src[x]] * inv_t;
    } else {
      const float* iv = inverse_vignette_.row(y);
      for (int x = 0; x < width_; ++x) dst[x] = inverse_response_[src[x]] * iv[x] * inv_t;
    }
  }
}

float PhotometricModel::response(float energy) const {
  const auto& g = inverse_response_;
  if (!(energy > g[0])) return 0.0f;  // also maps NaN to 0
  if (energy >= g[255]) return 255.0f;
  // First entry above `energy`: g[i - 1] <= energy < g[i], with i in [1, 255].
  const auto it = std::upper_bound(g.begin(), g.end(), energy);
  const int i = static_cast<int>(it - g.begin());
  const float lo = g[i - 1], hi = g[i];
  return static_cast<float>(i - 1) + (energy - lo) / (hi - lo);
}

void PhotometricModel::render(ImageView<const float> irradiance, ImageU8& out,
                              float exposure) const {
  checkArguments(irradiance.width, irradiance.height, exposure, "rendering");
  out.resize(width_, height_);
  for (int y = 0; y < height_; ++y) {
    const float* src = irradiance.row(y);
    const float* vig = vignette_.empty() ? nullptr : vignette_.row(y);
    std::uint8_t* dst = out.row(y);
    for (int x = 0; x < width_; ++x) {
      const float energy = exposure * src[x] * (vig != nullptr ? vig[x] : 1.0f);
      dst[x] = static_cast<std::uint8_t>(std::lround(response(energy)));
    }
  }
}

}  // namespace ldsm
