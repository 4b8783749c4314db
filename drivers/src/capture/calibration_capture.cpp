#include "ldsm/drivers/calibration_capture.h"

#include <cmath>
#include <cstdio>
#include <string>

#include "ldsm/error.h"

namespace ldsm::drivers {
namespace {

std::string ms(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%g ms", v);
  return buf;
}

}  // namespace

CapturedImages captureExposures(const ExposureSourceFactory& open,
                                const std::vector<double>& exposures_ms, int settle_frames,
                                const std::function<void(int, int)>& progress) {
  if (exposures_ms.empty()) throw ConfigError("exposure capture: no exposure times given");
  if (settle_frames < 0) throw ConfigError("exposure capture: settle frames must be >= 0");
  CapturedImages out;
  Frame frame;
  const int total = static_cast<int>(exposures_ms.size());
  for (int i = 0; i < total; ++i) {
    const double requested = exposures_ms[static_cast<std::size_t>(i)];
    if (!(std::isfinite(requested) && requested > 0))
      throw ConfigError("exposure capture: exposure " + ms(requested) + " is not positive");
    std::unique_ptr<FrameSource> source = open(requested);
    for (int f = 0; f <= settle_frames; ++f)
      if (!source->next(frame))
        throw DeviceError(ms(requested) + ": the camera stopped after " + std::to_string(f) +
                          " frames; check the device and its exposure range");
    out.images.push_back(frame.image);
    out.exposures_ms.push_back(
        std::isfinite(frame.exposure_ms) && frame.exposure_ms > 0 ? frame.exposure_ms : requested);
    if (progress) progress(i + 1, total);
  }
  return out;
}

std::vector<CapturedBoardView> captureBoardViews(
    FrameSource& source, const calib::BoardSpec& spec, const BoardCaptureOptions& options,
    const std::function<bool(int, std::int64_t)>& progress) {
  calib::validateBoardSpec(spec);
  if (options.views < 1 || options.max_frames < 0 || !(options.min_move_fraction >= 0) ||
      !(options.max_blur_px > 0))
    throw ConfigError("board capture: views must be >= 1, max_frames >= 0, blur limit > 0");
  std::vector<CapturedBoardView> kept;
  Frame frame;
  std::int64_t read = 0;
  while (static_cast<int>(kept.size()) < options.views &&
         (options.max_frames == 0 || read < options.max_frames) && source.next(frame)) {
    ++read;
    auto obs = calib::detectBoard(spec, frame.image.view());
    bool keep = obs && !(obs->blur_px > options.max_blur_px);
    if (keep) {
      const double min_move =
          options.min_move_fraction * std::hypot(frame.image.width(), frame.image.height());
      for (const auto& v : kept)
        if (calib::cornerDistance(v.observation, *obs) < min_move) {
          keep = false;
          break;
        }
    }
    if (keep)
      kept.push_back({frame.image, std::move(*obs), frame.index >= 0 ? frame.index : read - 1});
    if (progress && !progress(static_cast<int>(kept.size()), read)) break;
  }
  return kept;
}

}  // namespace ldsm::drivers
