#include "ldsm/drivers/sim/sim_options.h"

#include <cmath>
#include <sstream>

#include "ldsm/drivers/sim/det_math.h"
#include "ldsm/error.h"

namespace ldsm::drivers::sim {
namespace {

template <typename T>
void requireRange(const char* key, T value, T lo, T hi) {
  if (!(value >= lo && value <= hi)) {
    std::ostringstream os;
    os << "sim option " << key << " = " << value << " is outside [" << lo << ", " << hi << "]";
    throw ConfigError(os.str());
  }
}

}  // namespace

std::string toString(SimResponse response) {
  switch (response) {
    case SimResponse::Linear:
      return "linear";
    case SimResponse::Gamma:
      return "gamma";
    case SimResponse::SCurve:
      return "scurve";
  }
  return "?";
}

SimResponse parseSimResponse(const std::string& name) {
  if (name == "linear") return SimResponse::Linear;
  if (name == "gamma") return SimResponse::Gamma;
  if (name == "scurve") return SimResponse::SCurve;
  throw ConfigError("sim option response = '" + name + "' is not one of: linear, gamma, scurve");
}

void validate(const SimOptions& o) {
  requireRange("width", o.width, 16, 8192);
  requireRange("height", o.height, 16, 8192);
  requireRange("fps", o.fps, 1.0, 1000.0);
  if (o.focal_px != 0.0) requireRange("focal_px", o.focal_px, 1.0, 1e5);
  requireRange("hfov_deg", o.hfov_deg, 10.0, 150.0);
  requireRange<std::int64_t>("frames", o.frames, 0, 1000000);
  requireRange("exposure_ms", o.exposure_ms, 0.01, 1000.0);
  requireRange("vignette", o.vignette, 0.0, 0.9);
  requireRange("noise_sigma", o.noise_sigma, 0.0, 50.0);
  requireRange("supersampling", o.supersampling, 1, 4);
  requireRange("motion_blur_samples", o.motion_blur_samples, 1, 16);
  // The exposure (with changes up to 2x) must fit in the frame period.
  const double max_exposure = o.exposure_ms * (o.exposure_changes ? 2.0 : 1.0);
  if (o.motion_blur_samples > 1 && max_exposure > 1000.0 / o.fps) {
    std::ostringstream os;
    os << "sim option exposure_ms = " << o.exposure_ms
       << " is longer than the frame period at fps = " << o.fps << " (needed for motion blur)";
    throw ConfigError(os.str());
  }
}

double focalLengthPx(const SimOptions& o) {
  if (o.focal_px > 0.0) return o.focal_px;
  return 0.5 * static_cast<double>(o.width) / detTan(degToRad(0.5 * o.hfov_deg));
}

}  // namespace ldsm::drivers::sim
