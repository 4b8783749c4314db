// `ldsm calib ... --device /dev/videoN`: capturing the calibration data with a V4L2 camera. The
// captured images are saved (TUM-Mono layout for the photometric ones) so that the calibration
// can be repeated offline with --images / --sweep.
#pragma once

#include <string>
#include <vector>

#include "ldsm/calib/board_detection.h"
#include "ldsm/calib/camera_calibration.h"
#include "ldsm/drivers/calibration_capture.h"

namespace ldsm::app {

struct DeviceOptions {
  std::string device;  ///< empty: no camera
  int width = 0;       ///< 0: the camera's largest size
  int height = 0;
  double gain = -1.0;  ///< >= 0: fixed gain (auto-gain off); < 0: leave the camera's setting
};

/// Picks `views` board views from the camera's stream as the board is moved (at most
/// `max_frames` frames), writes them to images_dir/view_NNN.png and returns them as BoardViews;
/// `width` and `height` receive the image size. Progress goes to stderr.
std::vector<calib::BoardView> captureBoardFromDevice(const DeviceOptions& device,
                                                     const calib::BoardSpec& spec, int views,
                                                     std::int64_t max_frames,
                                                     const std::string& images_dir, int& width,
                                                     int& height);

/// An exposure sweep of `steps` exposures from min_ms to max_ms (log spaced), each with the
/// camera reopened at that exposure and `settle` frames dropped; written to dir (images/ and
/// times.txt).
drivers::CapturedImages captureSweepFromDevice(const DeviceOptions& device, double min_ms,
                                               double max_ms, int steps, int settle,
                                               const std::string& dir);

/// `frames` images of a flat surface at a fixed exposure (exposure_ms > 0, or auto-exposure
/// locked at its first value when 0), one every `every` frames so that the camera can be moved
/// between them; written to dir (images/ and times.txt).
drivers::CapturedImages captureFlatFromDevice(const DeviceOptions& device, double exposure_ms,
                                              int frames, int every, const std::string& dir);

}  // namespace ldsm::app
