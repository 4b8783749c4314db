#include "calib_device.h"

#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <system_error>

#include "ldsm/calib/image_file.h"
#include "ldsm/drivers/sim/photometric_sequences.h"
#include "ldsm/error.h"
#if LDSM_HAVE_V4L2
#include "ldsm/drivers/v4l2_source.h"
#endif

namespace ldsm::app {
namespace {

namespace fs = std::filesystem;

#if LDSM_HAVE_V4L2
drivers::V4l2Options v4l2Options(const DeviceOptions& d, double exposure_ms) {
  drivers::V4l2Options o;
  o.device = d.device;
  o.width = d.width;
  o.height = d.height;
  o.exposure_ms = exposure_ms;
  o.lock_auto_exposure = exposure_ms <= 0;
  o.gain = d.gain;
  return o;
}

void warnGain(const DeviceOptions& d) {
  if (d.gain < 0)
    spdlog::warn(
        "{}: no --gain given: if the camera has auto-gain it stays on, and brightness "
        "will not follow exposure; pass --gain to fix it",
        d.device);
}
#else
[[noreturn]] void noV4l2() {
  throw ConfigError("--device needs ldsm built with the V4L2 source (Linux, LDSM_WITH_V4L2)");
}
#endif

}  // namespace

std::vector<calib::BoardView> captureBoardFromDevice(const DeviceOptions& device,
                                                     const calib::BoardSpec& spec, int views,
                                                     std::int64_t max_frames,
                                                     const std::string& images_dir, int& width,
                                                     int& height) {
#if LDSM_HAVE_V4L2
  drivers::V4l2Options o;
  o.device = device.device;
  o.width = device.width;
  o.height = device.height;
  o.gain = device.gain;
  drivers::V4l2Source camera(o);
  width = camera.info().width;
  height = camera.info().height;
  std::fprintf(stderr,
               "calib: move the board in front of %s: near and far, tilted, into the image "
               "corners; a view is taken when the board is sharp and at a new place\n",
               device.device.c_str());
  drivers::BoardCaptureOptions capture;
  capture.views = views;
  capture.max_frames = max_frames;
  int last = -1;
  const auto captured =
      drivers::captureBoardViews(camera, spec, capture, [&](int kept, std::int64_t frames) {
        if (kept != last || frames % 100 == 0)
          std::fprintf(stderr, "calib: %d of %d views (%lld frames)\n", kept, views,
                       static_cast<long long>(frames));
        last = kept;
        return true;
      });
  std::error_code ec;
  fs::create_directories(images_dir, ec);
  std::vector<calib::BoardView> out;
  for (std::size_t i = 0; i < captured.size(); ++i) {
    char name[32];
    std::snprintf(name, sizeof(name), "view_%03zu.png", i);
    calib::writePng((fs::path(images_dir) / name).string(), captured[i].image.view());
    out.push_back({name, captured[i].observation});
  }
  return out;
#else
  (void)device, (void)spec, (void)views, (void)max_frames, (void)images_dir, (void)width,
      (void)height;
  noV4l2();
#endif
}

drivers::CapturedImages captureSweepFromDevice(const DeviceOptions& device, double min_ms,
                                               double max_ms, int steps, int settle,
                                               const std::string& dir) {
#if LDSM_HAVE_V4L2
  const auto times = drivers::sim::exposureSweepTimes(min_ms, max_ms, steps);
  warnGain(device);
  std::fprintf(stderr, "calib: keep the camera and the scene still during the sweep\n");
  const auto captured = drivers::captureExposures(
      [&](double t) { return std::make_unique<drivers::V4l2Source>(v4l2Options(device, t)); },
      times, settle,
      [](int done, int total) { std::fprintf(stderr, "calib: exposure %d of %d\n", done, total); });
  drivers::sim::writeExposedFrames(dir, captured.images, captured.exposures_ms);
  return captured;
#else
  (void)device, (void)min_ms, (void)max_ms, (void)steps, (void)settle, (void)dir;
  noV4l2();
#endif
}

drivers::CapturedImages captureFlatFromDevice(const DeviceOptions& device, double exposure_ms,
                                              int frames, int every, const std::string& dir) {
#if LDSM_HAVE_V4L2
  if (frames < 1 || every < 1)
    throw ConfigError("calib vignette: --frames and --every must be >= 1");
  warnGain(device);
  drivers::V4l2Source camera(v4l2Options(device, exposure_ms));
  std::fprintf(stderr,
               "calib: point %s at the flat surface; move it a little between the %d images\n",
               device.device.c_str(), frames);
  drivers::CapturedImages captured;
  drivers::Frame frame;
  for (std::int64_t i = 0; static_cast<int>(captured.images.size()) < frames; ++i) {
    if (!camera.next(frame)) throw DeviceError(device.device + ": the camera stopped");
    if (i < 4 || (i - 4) % every != 0) continue;  // the first frames: exposure settling
    captured.images.push_back(frame.image);
    captured.exposures_ms.push_back(std::isfinite(frame.exposure_ms) ? frame.exposure_ms : 1.0);
    std::fprintf(stderr, "calib: image %zu of %d\n", captured.images.size(), frames);
  }
  drivers::sim::writeExposedFrames(dir, captured.images, captured.exposures_ms);
  return captured;
#else
  (void)device, (void)exposure_ms, (void)frames, (void)every, (void)dir;
  noV4l2();
#endif
}

}  // namespace ldsm::app
