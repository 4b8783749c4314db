// Replays a recorded sequence as if it came from a camera: each frame is released at its own
// timestamp divided by `speed` (on std::chrono::steady_clock, relative to the first frame), never
// earlier. Frames the consumer does not take in time are not skipped here: the live pipeline's
// drop policy decides that, exactly as with a real camera whose frames queue up.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>

#include "ldsm/drivers/frame_source.h"

namespace ldsm::drivers {

class RealtimeReplaySource : public FrameSource {
 public:
  /// `speed` 1 plays at the recorded rate, 4 four times faster. Throws ldsm::ConfigError when
  /// speed is not a positive finite number (at most 1000) or `source` is null.
  RealtimeReplaySource(std::unique_ptr<FrameSource> source, double speed);

  /// The inner source's info, name prefixed "realtime:", nominal_fps scaled by the speed.
  SourceInfo info() const override;
  /// Reads the next frame from the inner source and waits until its release time. A frame whose
  /// timestamp is not after the previous one's is released at once.
  bool next(Frame& frame) override;

  double speed() const { return speed_; }
  /// How late the last frame was released after its scheduled time (the inner source decoded
  /// too slowly, or the caller came back late), in ms; 0 when on time.
  double lastLatenessMs() const { return last_lateness_ms_; }
  /// Largest lateness so far, in ms.
  double maxLatenessMs() const { return max_lateness_ms_; }

 private:
  std::unique_ptr<FrameSource> source_;
  double speed_;
  bool started_ = false;
  double first_timestamp_ = 0.0;
  std::chrono::steady_clock::time_point start_;
  double last_lateness_ms_ = 0.0;
  double max_lateness_ms_ = 0.0;
};

}  // namespace ldsm::drivers
