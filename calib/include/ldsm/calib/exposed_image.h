// An 8-bit image with the exposure time it was taken with: the input of the photometric
// calibrations (response_calibration.h, vignette_calibration.h).
#pragma once

#include <cstdint>
#include <string>

#include "ldsm/image.h"

namespace ldsm::calib {

struct ExposedImage {
  ImageView<const std::uint8_t> image;  ///< not owned: must outlive the calibration call
  double exposure_ms = 0.0;
  std::string name;  ///< named in messages (e.g. the file name)
};

}  // namespace ldsm::calib
