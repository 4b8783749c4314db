#include "v4l2/v4l2_enumerate.h"

#include <linux/videodev2.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>

#include "ldsm/error.h"

namespace ldsm::drivers::v4l2 {
namespace {

/// -EINVAL ends an enumeration; -ENOTTY means the driver does not enumerate this; anything else
/// is a device failure.
bool enumerationEnded(Device& device, int r, const char* what) {
  if (r >= 0) return false;
  if (r == -EINVAL || r == -ENOTTY) return true;
  throwDeviceError(device.path(), what, -r);
}

bool toFormat(std::uint32_t fourcc, V4l2PixelFormat& format) {
  switch (fourcc) {
    case V4L2_PIX_FMT_GREY:
      format = V4l2PixelFormat::Grey;
      return true;
    case V4L2_PIX_FMT_Y10:
      format = V4l2PixelFormat::Y10;
      return true;
    case V4L2_PIX_FMT_Y16:
      format = V4l2PixelFormat::Y16;
      return true;
    case V4L2_PIX_FMT_YUYV:
      format = V4l2PixelFormat::Yuyv;
      return true;
    case V4L2_PIX_FMT_MJPEG:
    case V4L2_PIX_FMT_JPEG:
      format = V4l2PixelFormat::Mjpeg;
      return true;
    default:
      return false;
  }
}

double fpsOf(const v4l2_fract& interval) {
  return interval.numerator > 0 ? static_cast<double>(interval.denominator) / interval.numerator
                                : 0.0;
}

void enumerateRates(Device& device, std::uint32_t fourcc, int width, int height,
                    V4l2FrameSize& size) {
  for (std::uint32_t index = 0;; ++index) {
    v4l2_frmivalenum e;
    std::memset(&e, 0, sizeof e);
    e.index = index;
    e.pixel_format = fourcc;
    e.width = static_cast<std::uint32_t>(width);
    e.height = static_cast<std::uint32_t>(height);
    if (enumerationEnded(device, device.ioctl(VIDIOC_ENUM_FRAMEINTERVALS, &e),
                         "VIDIOC_ENUM_FRAMEINTERVALS"))
      break;
    if (e.type == V4L2_FRMIVAL_TYPE_DISCRETE) {
      const double fps = fpsOf(e.discrete);
      if (fps > 0.0) size.fps.push_back(fps);
    } else {  // continuous or stepwise: the longest interval is the lowest rate
      size.min_fps = fpsOf(e.stepwise.max);
      size.max_fps = fpsOf(e.stepwise.min);
      break;
    }
  }
  std::sort(size.fps.begin(), size.fps.end(), [](double a, double b) { return a > b; });
}

std::vector<V4l2FrameSize> enumerateSizes(Device& device, std::uint32_t fourcc) {
  std::vector<V4l2FrameSize> sizes;
  for (std::uint32_t index = 0;; ++index) {
    v4l2_frmsizeenum e;
    std::memset(&e, 0, sizeof e);
    e.index = index;
    e.pixel_format = fourcc;
    if (enumerationEnded(device, device.ioctl(VIDIOC_ENUM_FRAMESIZES, &e),
                         "VIDIOC_ENUM_FRAMESIZES"))
      break;
    V4l2FrameSize size;
    if (e.type == V4L2_FRMSIZE_TYPE_DISCRETE) {
      size.min_width = size.max_width = static_cast<int>(e.discrete.width);
      size.min_height = size.max_height = static_cast<int>(e.discrete.height);
    } else {
      size.min_width = static_cast<int>(e.stepwise.min_width);
      size.max_width = static_cast<int>(e.stepwise.max_width);
      size.step_width = std::max(1, static_cast<int>(e.stepwise.step_width));
      size.min_height = static_cast<int>(e.stepwise.min_height);
      size.max_height = static_cast<int>(e.stepwise.max_height);
      size.step_height = std::max(1, static_cast<int>(e.stepwise.step_height));
    }
    enumerateRates(device, fourcc, size.max_width, size.max_height, size);
    sizes.push_back(size);
    if (e.type != V4L2_FRMSIZE_TYPE_DISCRETE) break;  // one range describes them all
  }
  return sizes;
}

}  // namespace

void checkCaptureDevice(Device& device) {
  v4l2_capability cap;
  std::memset(&cap, 0, sizeof cap);
  device.ioctlOrThrow(VIDIOC_QUERYCAP, &cap, "VIDIOC_QUERYCAP");
  const std::uint32_t caps =
      (cap.capabilities & V4L2_CAP_DEVICE_CAPS) != 0 ? cap.device_caps : cap.capabilities;
  if ((caps & V4L2_CAP_VIDEO_CAPTURE) == 0 || (caps & V4L2_CAP_STREAMING) == 0) {
    char hex[16];
    std::snprintf(hex, sizeof hex, "0x%08x", caps);
    throw DeviceError(
        device.path() + ": not a video capture device with streaming I/O ('" +
        std::string(reinterpret_cast<const char*>(cap.card),
                    strnlen(reinterpret_cast<const char*>(cap.card), sizeof cap.card)) +
        "', capabilities " + hex +
        "); a camera often has several /dev/video nodes: `v4l2-ctl "
        "--list-devices` shows which one captures");
  }
}

std::vector<V4l2FormatDescription> enumerateFormats(Device& device) {
  std::vector<V4l2FormatDescription> formats;
  for (std::uint32_t index = 0;; ++index) {
    v4l2_fmtdesc f;
    std::memset(&f, 0, sizeof f);
    f.index = index;
    f.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    if (enumerationEnded(device, device.ioctl(VIDIOC_ENUM_FMT, &f), "VIDIOC_ENUM_FMT")) break;
    V4l2FormatDescription d;
    d.fourcc = f.pixelformat;
    d.description =
        std::string(reinterpret_cast<const char*>(f.description),
                    strnlen(reinterpret_cast<const char*>(f.description), sizeof f.description));
    d.supported = toFormat(f.pixelformat, d.format);
    d.sizes = enumerateSizes(device, f.pixelformat);
    formats.push_back(std::move(d));
  }
  return formats;
}

}  // namespace ldsm::drivers::v4l2

namespace ldsm::drivers {

std::vector<V4l2FormatDescription> listV4l2Formats(const std::string& device,
                                                   std::shared_ptr<V4l2Kernel> kernel) {
  v4l2::Device d(std::move(kernel), device);
  v4l2::checkCaptureDevice(d);
  return v4l2::enumerateFormats(d);
}

}  // namespace ldsm::drivers
