// Recording any frame source (a camera, usually) in the TUM-Mono layout that `ldsm run` and
// openDataset() read back:
//   out_dir/images/000000.png ...  8-bit grey frames (PNG)
//   out_dir/times.txt               "000000 <timestamp s> [<exposure ms>]" per frame
// The timestamps are the source's (kernel timestamps for a camera); the exposure column is
// present for the frames whose exposure is known. Each frame's image is written before its
// line in times.txt and the line is flushed at once, so that an interrupted recording is still
// a valid sequence of the frames recorded so far.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "ldsm/drivers/frame_source.h"

namespace ldsm::drivers {

struct RecordOptions {
  std::int64_t max_frames = 0;  ///< 0: until the source ends or the callback stops it
  bool overwrite = false;       ///< replace an earlier recording in out_dir instead of refusing
  int png_compression = 1;      ///< zlib level 0..9: fast by default, to keep up with the camera
};

struct RecordSummary {
  std::int64_t frames = 0;        ///< frames written
  std::int64_t out_of_order = 0;  ///< frames not written: timestamp not after the previous one
  std::int64_t gaps = 0;          ///< intervals longer than 1.5 frame periods (frames lost
                                  ///< upstream), when the source's frame rate is known
  double first_timestamp = 0.0;
  double last_timestamp = 0.0;
  std::string out_dir;
};

/// Called after each written frame with the frame and the number written so far; return false
/// to stop recording (for example on Ctrl-C).
using RecordCallback = std::function<bool(const Frame& frame, std::int64_t written)>;

/// Records `source` into `out_dir` (created if needed). Throws ldsm::Error when out_dir already
/// holds a recording and `overwrite` is false, or when a file cannot be written; when the source
/// fails (camera unplugged...), rethrows its ldsm::DeviceError / InputError with "N frames
/// recorded so far are kept in <out_dir>" appended, after closing times.txt.
RecordSummary recordTumMono(FrameSource& source, const std::string& out_dir,
                            const RecordOptions& options = {}, const RecordCallback& on_frame = {});

}  // namespace ldsm::drivers
