#include "ldsm/calib/pinhole_guess.h"

#include <cmath>
#include <sstream>

#include "ldsm/error.h"

namespace ldsm::calib {

GeometricCalibration pinholeFromFieldOfView(int width, int height, double horizontal_fov_deg) {
  if (!std::isfinite(horizontal_fov_deg) || horizontal_fov_deg < kMinGuessFovDeg ||
      horizontal_fov_deg > kMaxGuessFovDeg) {
    std::ostringstream msg;
    msg << "--fov: " << horizontal_fov_deg << " is not a horizontal field of view in ["
        << kMinGuessFovDeg << ", " << kMaxGuessFovDeg << "] degrees";
    throw ConfigError(msg.str());
  }
  if (width <= 0 || height <= 0)
    throw InputError("--fov: the image size " + std::to_string(width) + "x" +
                     std::to_string(height) + " is not positive");
  constexpr double kPi = 3.14159265358979323846;
  const double f = 0.5 * width / std::tan(0.5 * horizontal_fov_deg * kPi / 180.0);
  GeometricCalibration c;
  c.input.model = CameraModelType::Pinhole;
  c.input.fx = f;
  c.input.fy = f;
  c.input.cx = 0.5 * (width - 1);
  c.input.cy = 0.5 * (height - 1);
  c.input.width = width;
  c.input.height = height;
  c.output.mode = OutputMode::None;
  c.output.width = width;
  c.output.height = height;
  return c;
}

}  // namespace ldsm::calib
