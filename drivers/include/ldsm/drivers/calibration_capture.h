// Capturing calibration data with a live camera (`ldsm calib ... --device`): board views picked
// from the stream as the board is moved around, and exposure sweeps driven by opening the camera
// at each exposure time with auto-exposure and auto-gain off.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "ldsm/calib/board_detection.h"
#include "ldsm/drivers/frame_source.h"
#include "ldsm/image.h"

namespace ldsm::drivers {

/// Opens the camera with a fixed exposure time in ms (auto-exposure and auto-gain off).
using ExposureSourceFactory = std::function<std::unique_ptr<FrameSource>(double exposure_ms)>;

struct CapturedImages {
  std::vector<ImageU8> images;
  /// Exposure per image as the camera reports it (the requested one when it reports none).
  std::vector<double> exposures_ms;
};

/// For each of `exposures_ms` in order: opens a source with `open`, drops `settle_frames` frames
/// (the exposure may take a few frames to apply) and keeps the next one. `progress(done, total)`
/// is called after each. Throws ldsm::ConfigError for an empty list or a negative settle count,
/// ldsm::DeviceError "<exposure> ms: the camera stopped ..." when a source ends early, and passes
/// on the sources' own errors.
CapturedImages captureExposures(const ExposureSourceFactory& open,
                                const std::vector<double>& exposures_ms, int settle_frames = 4,
                                const std::function<void(int, int)>& progress = {});

struct BoardCaptureOptions {
  int views = 20;               ///< stop when this many views are kept
  std::int64_t max_frames = 0;  ///< stop after this many frames (0: when the source ends)
  /// A frame is kept only when its corners moved by at least this fraction of the image diagonal
  /// (root mean square) from every view kept so far...
  double min_move_fraction = 0.05;
  /// ...and its edge blur is at most this many pixels (no motion blur).
  double max_blur_px = 1.5;
};

struct CapturedBoardView {
  ImageU8 image;
  calib::BoardObservation observation;
  std::int64_t frame_index = 0;  ///< position in the stream
};

/// Reads frames from `source`, detects the board in each and keeps those that show it sharp and
/// at a new position, until `views` are kept, max_frames were read or the source ends.
/// `progress(kept, frames_read)` is called after each frame; returning false stops the capture.
/// Throws ldsm::ConfigError for an invalid spec or options; passes on the source's errors.
std::vector<CapturedBoardView> captureBoardViews(
    FrameSource& source, const calib::BoardSpec& spec, const BoardCaptureOptions& options,
    const std::function<bool(int, std::int64_t)>& progress = {});

}  // namespace ldsm::drivers
