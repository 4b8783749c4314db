// Photometric calibration files in the TUM-Mono / DSO layout: pcalib.txt (the inverse response
// G^-1 as 256 whitespace-separated numbers, entry v = irradiance of pixel value v, usually in
// [0, 255]) and vignette.png (V as an 8- or 16-bit single-channel PNG, scaled to a maximum of 1).
#pragma once

#include <array>
#include <string>

#include "ldsm/camera/calibration.h"
#include "ldsm/image.h"

namespace ldsm::calib {

/// Reads pcalib.txt. Throws ldsm::InputError "path:line: what" when a value is not a finite
/// number, the count is not 256, or the values decrease (naming the first bad index) or are all
/// equal.
std::array<float, 256> readInverseResponse(const std::string& path);

/// Writes 256 values on one line, each exactly representable on reading.
void writeInverseResponse(const std::string& path, const std::array<float, 256>& inverse_response);

/// Reads a vignette image scaled so that its maximum is 1. Throws ldsm::InputError "path: what"
/// when it cannot be read, is not single-channel 8/16-bit, or has a zero pixel (naming it).
ImageF readVignette(const std::string& path);

/// Writes a 16-bit PNG scaled so that the maximum of `vignette` becomes 65535. Throws
/// ldsm::InputError for an empty image or values that are not finite and positive.
void writeVignette(const std::string& path, const ImageF& vignette);

/// Loads whichever of the two files is given (an empty path: not known) for images of
/// width x height and validates the result (validatePhotometricCalibration). Pass width = height
/// = 0 to skip the vignette size check.
PhotometricCalibration loadPhotometricCalibration(const std::string& pcalib_path,
                                                  const std::string& vignette_path, int width,
                                                  int height);

}  // namespace ldsm::calib
