#include "ldsm/drivers/realtime_replay_source.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <thread>
#include <utility>

#include "ldsm/error.h"

namespace ldsm::drivers {

RealtimeReplaySource::RealtimeReplaySource(std::unique_ptr<FrameSource> source, double speed)
    : source_(std::move(source)), speed_(speed) {
  if (!source_) throw ConfigError("realtime replay: no source given");
  if (!std::isfinite(speed) || speed <= 0.0 || speed > 1000.0)
    throw ConfigError("realtime replay: speed = " + std::to_string(speed) +
                      " is outside (0, 1000]");
}

SourceInfo RealtimeReplaySource::info() const {
  SourceInfo info = source_->info();
  info.name = "realtime:" + info.name;
  info.nominal_fps *= speed_;
  return info;
}

bool RealtimeReplaySource::next(Frame& frame) {
  using Clock = std::chrono::steady_clock;
  if (!source_->next(frame)) return false;
  const Clock::time_point now = Clock::now();
  if (!started_) {
    started_ = true;
    first_timestamp_ = frame.timestamp;
    start_ = now;
    last_lateness_ms_ = 0.0;
    return true;
  }
  const double offset_s = std::max(0.0, (frame.timestamp - first_timestamp_) / speed_);
  const Clock::time_point release =
      start_ + std::chrono::ceil<Clock::duration>(std::chrono::duration<double>(offset_s));
  // sleep_until may wake early on some platforms: loop until the release time has passed.
  while (Clock::now() < release) std::this_thread::sleep_until(release);
  const double late_ms =
      std::chrono::duration<double, std::milli>(now - release).count();  // > 0 when overdue
  last_lateness_ms_ = std::max(0.0, late_ms);
  max_lateness_ms_ = std::max(max_lateness_ms_, last_lateness_ms_);
  return true;
}

}  // namespace ldsm::drivers
