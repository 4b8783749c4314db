// The one interface every frame source implements: datasets, synthetic scenes, V4L2, libcamera,
// real-time replay. A source yields 8-bit grey frames with a timestamp and, when known, the
// exposure time.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string>

#include "ldsm/camera/calibration.h"
#include "ldsm/image.h"

namespace ldsm::drivers {

struct Frame {
  std::int64_t index = -1;  ///< 0-based position in the stream
  double timestamp = 0.0;   ///< seconds
  double exposure_ms = std::numeric_limits<double>::quiet_NaN();  ///< NaN when unknown
  ImageU8 image;  ///< grey, reused across next() calls (no reallocation per frame)
};

/// What a source knows about its stream up front.
struct SourceInfo {
  std::string name;  ///< e.g. "tum-mono", "euroc", "sim:loop", "v4l2:/dev/video0"
  int width = 0;
  int height = 0;
  std::int64_t frame_count = -1;  ///< -1 when unbounded (live camera)
  double nominal_fps = 0.0;       ///< 0 when unknown
};

class FrameSource {
 public:
  virtual ~FrameSource() = default;
  virtual SourceInfo info() const = 0;
  /// Fills `frame` with the next frame. Returns false at the end of the stream.
  /// Throws ldsm::InputError / ldsm::DeviceError naming the file or device on failure; after an
  /// error the source is at end of stream.
  virtual bool next(Frame& frame) = 0;
};

}  // namespace ldsm::drivers
