// PNG plots written by `ldsm calib`: the recovered inverse response with its monotonicity check,
// the vignette (image and radial profile), and the image coverage of a camera calibration.
#pragma once

#include <array>
#include <string>

#include "ldsm/calib/camera_calibration.h"
#include "ldsm/calib/response_calibration.h"
#include "ldsm/calib/vignette_calibration.h"

namespace ldsm::app {

/// G^-1 over the pixel values: the written (non-decreasing) curve, the raw estimate per value,
/// the values where the estimate decreases, and `reference` (a known G^-1, e.g. the simulator's)
/// when not null. Throws ldsm::Error when the file cannot be written.
void writeResponsePlot(const std::string& path, const calib::ResponseCalibrationResult& result,
                       const std::array<float, 256>* reference);

/// The vignette as a heat map with its centre, and its radial profile: the measured average
/// against the fitted model.
void writeVignettePlot(const std::string& path, const calib::VignetteCalibrationResult& result);

/// Where in the image the corners of the used views were, coloured by reprojection error.
void writeCoveragePlot(const std::string& path, const calib::CameraCalibrationResult& result,
                       int width, int height);

}  // namespace ldsm::app
