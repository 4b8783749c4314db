// Whether a saved map fits the camera at hand (docs/map-file.md, "Calibration"): a map is only
// valid for the rectified pinhole and the photometric correction it was made with.
#pragma once

#include <cstdint>
#include <string>

#include "ldsm/camera/calibration.h"
#include "mapfile/map_data.h"

namespace ldsm {

/// "" when a map saved with `saved` can be used with `now`; otherwise what differs, with both
/// values: the image size, fx, fy, cx, cy (relative tolerance 1e-5), the photometric calibration
/// (response, vignette, their hash). radial_k is an estimate of the run, not compared.
std::string mapCalibrationMismatch(const MapCalibration& saved, const MapCalibration& now);

/// FNV-1a (64 bit) of the inverse response (when known) and the vignette (when known, with its
/// size), each float as its little-endian bits; 0 when neither is known.
std::uint64_t photometricHash(const PhotometricCalibration& photometric);

/// The MapCalibration of a rectified camera and its photometric calibration.
MapCalibration makeMapCalibration(const PinholeIntrinsics& camera, double radial_k,
                                  const PhotometricCalibration& photometric);

}  // namespace ldsm
