// What `ldsm calib` prints and writes about a calibration: the per-view report of a camera
// calibration, and the summaries on stdout (warnings go to the log, stderr).
#pragma once

#include <array>
#include <cstddef>
#include <string>

#include "ldsm/calib/board_detection.h"
#include "ldsm/calib/camera_calibration.h"
#include "ldsm/calib/response_calibration.h"
#include "ldsm/calib/vignette_calibration.h"

namespace ldsm::app {

/// calibration_report.txt: a header naming the source, board and model, one line per view
/// ("name status corners blur_px rms_px reason") and the overall figures.
std::string cameraReportText(const std::string& source, const calib::BoardSpec& spec,
                             const std::string& model, const calib::CameraCalibrationResult& r);

/// The per-view table, the intrinsics and the RMS; `written` names the files. Then the warnings.
void printCameraSummary(const calib::CameraCalibrationResult& r, const std::string& written);

/// Images used, observed values, monotonicity, residual and noise, and the difference to
/// `reference` when not null (after scaling it to 255 at 255). Then the warnings.
void printResponseSummary(const calib::ResponseCalibrationResult& r, std::size_t images,
                          const std::array<float, 256>* reference, const std::string& written);

/// Images used, centre, model, minimum and fit residual. Then the warnings.
void printVignetteSummary(const calib::VignetteCalibrationResult& r, std::size_t images,
                          const std::string& written);

}  // namespace ldsm::app
