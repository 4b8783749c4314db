// The calibration that goes with a recorded sequence: the geometric calibration file found in the
// dataset (or given explicitly) and the photometric files beside it.
#pragma once

#include <string>

#include "ldsm/camera/calibration.h"
#include "ldsm/drivers/dataset_description.h"

namespace ldsm::drivers {

struct DatasetCalibration {
  GeometricCalibration geometric;
  PhotometricCalibration photometric;
  std::string geometric_source;    ///< file the geometric calibration came from
  std::string photometric_source;  ///< files of the photometric calibration, or "none"
};

/// Loads the calibration of `dataset`; a non-empty `calib_file` replaces the dataset's own.
/// With `guess_fov_deg` non-zero the geometric calibration is not read at all: it is a pinhole of
/// that horizontal field of view (calib/pinhole_guess.h) at the images' size, for a camera without
/// a calibration (the online refinement then has to find the rest); the photometric files are still
/// read. Throws ldsm::InputError naming the file at fault, or saying that none was found (and how
/// to start without one), or when the calibration's input size differs from the images';
/// ldsm::ConfigError when both a file and a guess are given, or the guess is out of range.
DatasetCalibration loadDatasetCalibration(const DatasetDescription& dataset,
                                          const std::string& calib_file = {},
                                          double guess_fov_deg = 0.0);

}  // namespace ldsm::drivers
