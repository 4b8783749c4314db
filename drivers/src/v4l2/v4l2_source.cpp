// V4l2Source: opening, negotiation, streaming and per-frame conversion (see v4l2_source.h).
#include "ldsm/drivers/v4l2_source.h"

#include <linux/videodev2.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <optional>
#include <string>
#include <utility>

#include "ldsm/error.h"
#include "v4l2/v4l2_controls.h"
#include "v4l2/v4l2_convert.h"
#include "v4l2/v4l2_device.h"
#include "v4l2/v4l2_enumerate.h"
#include "v4l2/v4l2_stream.h"

namespace ldsm::drivers {
namespace {

/// Bad frames in a row after which the stream is declared broken.
constexpr int kMaxBadFramesInARow = 30;

v4l2::FrameLayout setFormat(v4l2::Device& device, V4l2Mode& mode) {
  v4l2_format f;
  std::memset(&f, 0, sizeof f);
  f.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (mode.width == 0) {  // size not enumerated and not requested: keep the current one
    device.ioctlOrThrow(VIDIOC_G_FMT, &f, "reading the format (VIDIOC_G_FMT)");
    mode.width = static_cast<int>(f.fmt.pix.width);
    mode.height = static_cast<int>(f.fmt.pix.height);
  }
  std::memset(&f, 0, sizeof f);
  f.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  f.fmt.pix.width = static_cast<std::uint32_t>(mode.width);
  f.fmt.pix.height = static_cast<std::uint32_t>(mode.height);
  f.fmt.pix.pixelformat = v4l2FourCc(mode.format);
  f.fmt.pix.field = V4L2_FIELD_NONE;
  const int r = device.ioctl(VIDIOC_S_FMT, &f);
  if (r < 0)
    v4l2::throwDeviceError(device.path(),
                           std::string("setting format ") + toString(mode.format) + " " +
                               std::to_string(mode.width) + "x" + std::to_string(mode.height),
                           -r);
  const bool jpeg_alias =
      mode.format == V4l2PixelFormat::Mjpeg && f.fmt.pix.pixelformat == V4L2_PIX_FMT_JPEG;
  if ((f.fmt.pix.pixelformat != v4l2FourCc(mode.format) && !jpeg_alias) ||
      static_cast<int>(f.fmt.pix.width) != mode.width ||
      static_cast<int>(f.fmt.pix.height) != mode.height)
    throw DeviceError(device.path() + ": format not supported: asked for " + toString(mode.format) +
                      " " + std::to_string(mode.width) + "x" + std::to_string(mode.height) +
                      ", the driver set " + fourCcToString(f.fmt.pix.pixelformat) + " " +
                      std::to_string(f.fmt.pix.width) + "x" + std::to_string(f.fmt.pix.height) +
                      "; choose a format and size from `ldsm record --list-formats`");
  if (f.fmt.pix.field != V4L2_FIELD_NONE && f.fmt.pix.field != V4L2_FIELD_ANY)
    spdlog::warn("{}: interlaced video (field order {}): frames mix two fields", device.path(),
                 f.fmt.pix.field);
  v4l2::FrameLayout layout;
  layout.format = mode.format;
  layout.width = mode.width;
  layout.height = mode.height;
  layout.bytes_per_line = f.fmt.pix.bytesperline;
  return layout;
}

/// Sets the frame rate when requested and possible; returns the device's rate (0 if unknown).
double setFrameRate(v4l2::Device& device, double fps) {
  v4l2_streamparm p;
  std::memset(&p, 0, sizeof p);
  p.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (device.ioctl(VIDIOC_G_PARM, &p) < 0) {
    if (fps > 0.0) spdlog::warn("{}: the driver cannot set the frame rate", device.path());
    return fps;
  }
  if (fps > 0.0) {
    if ((p.parm.capture.capability & V4L2_CAP_TIMEPERFRAME) == 0) {
      spdlog::warn("{}: the driver cannot set the frame rate; keeping its own", device.path());
    } else {
      const bool whole = std::fabs(fps - std::round(fps)) < 1e-6;
      p.parm.capture.timeperframe.numerator = whole ? 1 : 1000;
      p.parm.capture.timeperframe.denominator =
          static_cast<std::uint32_t>(std::llround(whole ? fps : fps * 1000.0));
      device.ioctlOrThrow(VIDIOC_S_PARM, &p, "setting the frame rate (VIDIOC_S_PARM)");
    }
  }
  const v4l2_fract t = p.parm.capture.timeperframe;
  return t.numerator > 0 && t.denominator > 0 ? static_cast<double>(t.denominator) / t.numerator
                                              : fps;
}

double steadyNowSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

struct V4l2Source::Impl {
  V4l2Options options;
  std::optional<v4l2::Device> device;
  std::vector<V4l2FormatDescription> offered;
  V4l2Mode mode;
  v4l2::FrameLayout layout;
  double device_fps = 0.0;
  std::optional<v4l2::ExposureControls> controls;
  std::optional<v4l2::MmapStream> stream;
  std::int64_t next_index = 0;
  std::int64_t skipped = 0;
  int bad_in_a_row = 0;
  bool ended = false;
  std::string problem;

  /// Frees the device at once (stream first): after an error the camera is free for others.
  void shutDown() noexcept {
    ended = true;
    stream.reset();
    controls.reset();
    device.reset();
  }

  bool nextFrame(Frame& frame) {
    for (;;) {
      const v4l2::FilledBuffer b = stream->dequeue(options.poll_timeout_ms);
      bool good = !b.corrupt;
      if (!good) problem = "the driver flagged the frame as corrupt";
      if (good) good = v4l2::convertToGrey(layout, b.data, b.bytes_used, frame.image, problem);
      stream->requeue(b.index);
      if (!good) {
        ++skipped;
        spdlog::warn("{}: frame skipped: {}", options.device, problem);
        if (++bad_in_a_row >= kMaxBadFramesInARow)
          throw DeviceError(options.device + ": " + std::to_string(bad_in_a_row) +
                            " bad frames in a row (last: " + problem +
                            "); try another pixel format or a lower resolution");
        continue;
      }
      bad_in_a_row = 0;
      frame.index = next_index++;
      frame.timestamp = b.monotonic && b.timestamp > 0.0 ? b.timestamp : steadyNowSeconds();
      frame.exposure_ms = controls->readExposureMs(*device);
      return true;
    }
  }
};

V4l2Source::V4l2Source(const V4l2Options& options, std::shared_ptr<V4l2Kernel> kernel)
    : impl_(std::make_unique<Impl>()) {
  validate(options);
  Impl& s = *impl_;
  s.options = options;
  s.device.emplace(std::move(kernel), options.device);
  v4l2::checkCaptureDevice(*s.device);
  s.offered = v4l2::enumerateFormats(*s.device);
  s.mode = chooseV4l2Mode(s.offered, options);
  s.layout = setFormat(*s.device, s.mode);
  s.device_fps = setFrameRate(*s.device, s.mode.fps);
  s.controls.emplace(*s.device, options);
  s.stream.emplace(*s.device, options.buffer_count);
  s.stream->start();
  spdlog::info("{}: streaming {} {}x{} at {} fps with {} buffers", options.device,
               toString(s.mode.format), s.mode.width, s.mode.height, s.device_fps,
               s.stream->count());
}

V4l2Source::~V4l2Source() = default;

SourceInfo V4l2Source::info() const {
  SourceInfo info;
  info.name = "v4l2:" + impl_->options.device;
  info.width = impl_->mode.width;
  info.height = impl_->mode.height;
  info.frame_count = -1;
  info.nominal_fps = impl_->device_fps;
  return info;
}

bool V4l2Source::next(Frame& frame) {
  if (impl_->ended) return false;
  try {
    return impl_->nextFrame(frame);
  } catch (...) {
    impl_->shutDown();
    throw;
  }
}

const V4l2Mode& V4l2Source::mode() const {
  return impl_->mode;
}
const std::vector<V4l2FormatDescription>& V4l2Source::offeredFormats() const {
  return impl_->offered;
}
int V4l2Source::bufferCount() const {
  return impl_->stream ? impl_->stream->count() : 0;
}
std::int64_t V4l2Source::skippedFrames() const {
  return impl_->skipped;
}

}  // namespace ldsm::drivers
