// `ldsm record`: records a V4L2 camera into a TUM-Mono folder (images/, times.txt with the
// exposure of each frame) that `ldsm run --dataset DIR` reads back. Ctrl-C stops cleanly; so does
// an unplugged camera, keeping what was recorded. `ldsm record --device D --list-formats` prints
// what the camera offers.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "commands.h"
#include "interrupt.h"
#include "ldsm/drivers/tum_mono_recorder.h"
#include "ldsm/drivers/v4l2_source.h"
#include "ldsm/error.h"

namespace ldsm::app {
namespace {

struct RecordCommandOptions {
  std::string device = "/dev/video0";
  std::string out;
  std::int64_t frames = 0;
  std::string formats;  // comma-separated preference list; empty: the default order
  int width = 0;
  int height = 0;
  double fps = 0.0;
  double exposure_ms = 0.0;
  double gain = -1.0;
  bool lock_exposure = false;
  int buffers = 4;
  int timeout_ms = 2000;
  bool overwrite = false;
  bool list_formats = false;
};

#if defined(LDSM_HAVE_V4L2)

std::vector<drivers::V4l2PixelFormat> parseFormats(const std::string& list) {
  std::vector<drivers::V4l2PixelFormat> formats;
  std::stringstream ss(list);
  std::string name;
  while (std::getline(ss, name, ','))
    if (!name.empty()) formats.push_back(drivers::parseV4l2PixelFormat(name));
  return formats;
}

int runRecord(const RecordCommandOptions& o) {
  if (o.list_formats) {
    std::printf("%s:\n%s", o.device.c_str(),
                drivers::describeV4l2Formats(drivers::listV4l2Formats(o.device)).c_str());
    return 0;
  }
  if (o.out.empty()) throw ConfigError("record: --out is required");
  drivers::V4l2Options camera;
  camera.device = o.device;
  if (!o.formats.empty()) camera.formats = parseFormats(o.formats);
  camera.width = o.width;
  camera.height = o.height;
  camera.fps = o.fps;
  camera.exposure_ms = o.exposure_ms;
  camera.gain = o.gain;
  camera.lock_auto_exposure = o.lock_exposure;
  camera.buffer_count = o.buffers;
  camera.poll_timeout_ms = o.timeout_ms;
  drivers::RecordOptions record;
  record.max_frames = o.frames;
  record.overwrite = o.overwrite;

  drivers::V4l2Source source(camera);
  const drivers::V4l2Mode& mode = source.mode();
  std::fprintf(stderr, "record: %s %s %dx%d at %g fps -> %s (Ctrl-C stops)\n", o.device.c_str(),
               drivers::toString(mode.format), mode.width, mode.height, source.info().nominal_fps,
               o.out.c_str());
  const InterruptHandler interrupt;  // Ctrl-C or SIGTERM: stop after the current frame
  const bool tty = isatty(fileno(stderr)) != 0;
  auto last_report = std::chrono::steady_clock::now();
  const drivers::RecordSummary s = drivers::recordTumMono(
      source, o.out, record, [&](const drivers::Frame& frame, std::int64_t written) {
        const auto now = std::chrono::steady_clock::now();
        if (now - last_report >= std::chrono::seconds(1)) {
          last_report = now;
          std::fprintf(stderr, "%srecord: %lld frames, exposure %.2f ms%s", tty ? "\r" : "",
                       static_cast<long long>(written), frame.exposure_ms, tty ? "" : "\n");
          std::fflush(stderr);
        }
        return !InterruptHandler::requested();
      });
  if (tty) std::fputc('\n', stderr);
  const double span = s.last_timestamp - s.first_timestamp;
  std::printf("recorded %lld frames (%s %dx%d, %.2f fps measured) to %s\n",
              static_cast<long long>(s.frames), drivers::toString(mode.format), mode.width,
              mode.height, s.frames > 1 && span > 0.0 ? (s.frames - 1) / span : 0.0, o.out.c_str());
  if (source.skippedFrames() > 0)
    std::printf("skipped %lld corrupt frames\n", static_cast<long long>(source.skippedFrames()));
  if (s.gaps > 0)
    std::printf(
        "%lld gaps in the timestamps: frames were lost before the recorder (lower the "
        "resolution or frame rate, or record to a faster disk)\n",
        static_cast<long long>(s.gaps));
  return 0;
}

#else

int runRecord(const RecordCommandOptions&) {
  throw DeviceError("record: this ldsm was built without the V4L2 source (Linux only)");
}

#endif

}  // namespace

void addRecordCommand(CLI::App& app, CommandResult& result) {
  auto options = std::make_shared<RecordCommandOptions>();
  CLI::App* sub = app.add_subcommand(
      "record", "Record a V4L2 camera into a TUM-Mono folder (images/, times.txt with exposures)");
  sub->add_option("--device", options->device, "V4L2 device")->capture_default_str();
  sub->add_option("--out", options->out, "Output folder (created)");
  sub->add_option("--frames", options->frames, "Frames to record (0: until Ctrl-C)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  sub->add_option("--format", options->formats,
                  "Pixel formats in order of preference, comma-separated: GREY, Y10, Y16, YUYV, "
                  "MJPEG (default: that order)");
  sub->add_option("--width", options->width, "Frame width (0 with --height 0: the largest)")
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--height", options->height, "Frame height")->check(CLI::NonNegativeNumber);
  sub->add_option("--fps", options->fps, "Frame rate (0: the camera's)")
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--exposure-ms", options->exposure_ms,
                  "Manual exposure in ms (auto exposure off; 0: automatic)")
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--gain", options->gain, "Manual gain in the camera's units (default: auto)");
  sub->add_flag("--lock-exposure", options->lock_exposure,
                "Freeze the automatic exposure at its value when recording starts");
  sub->add_option("--buffers", options->buffers, "Kernel buffers (2..32)")->capture_default_str();
  sub->add_option("--timeout-ms", options->timeout_ms, "Longest wait for a frame")
      ->capture_default_str();
  sub->add_flag("--overwrite", options->overwrite, "Replace an earlier recording in --out");
  sub->add_flag("--list-formats", options->list_formats,
                "Print the camera's formats, sizes and frame rates, and exit");
  sub->callback([options, &result] { result.exit_code = runRecord(*options); });
}

}  // namespace ldsm::app
