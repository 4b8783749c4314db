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
/// Throws ldsm::InputError naming the file at fault, or saying that none was found, or when the
/// calibration's input size differs from the images'.
DatasetCalibration loadDatasetCalibration(const DatasetDescription& dataset,
                                          const std::string& calib_file = {});

}  // namespace ldsm::drivers
