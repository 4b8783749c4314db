// V4L2 pixel format names, option validation and the choice of format, size and frame rate
// among what a device offers. No kernel calls here.
#include <linux/videodev2.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <string>

#include "ldsm/drivers/v4l2_source.h"
#include "ldsm/error.h"

namespace ldsm::drivers {
namespace {

std::string upper(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
  return s;
}

std::string fpsText(double fps) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", fps);
  return buf;
}

bool onStep(int value, int min, int step) {
  return step <= 1 || (value - min) % step == 0;
}

/// The offered rate closest to `wanted` (0 when none is listed and there is no range).
double chooseFps(const V4l2FrameSize& size, double wanted) {
  if (wanted <= 0.0) return 0.0;
  if (!size.fps.empty()) {
    double best = size.fps.front();
    for (double f : size.fps)
      if (std::fabs(f - wanted) < std::fabs(best - wanted)) best = f;
    return best;
  }
  if (size.max_fps > 0.0) return std::clamp(wanted, size.min_fps, size.max_fps);
  return wanted;  // the device lists no rates: ask for it and read back what it set
}

std::string preferenceList(const std::vector<V4l2PixelFormat>& formats) {
  std::string s;
  for (std::size_t i = 0; i < formats.size(); ++i) {
    if (i > 0) s += i + 1 == formats.size() ? " or " : ", ";
    s += toString(formats[i]);
  }
  return s;
}

}  // namespace

const char* toString(V4l2PixelFormat format) {
  switch (format) {
    case V4l2PixelFormat::Grey:
      return "GREY";
    case V4l2PixelFormat::Y10:
      return "Y10";
    case V4l2PixelFormat::Y16:
      return "Y16";
    case V4l2PixelFormat::Yuyv:
      return "YUYV";
    case V4l2PixelFormat::Mjpeg:
      return "MJPEG";
  }
  return "?";
}

V4l2PixelFormat parseV4l2PixelFormat(const std::string& name) {
  const std::string n = upper(name);
  if (n == "GREY" || n == "GRAY") return V4l2PixelFormat::Grey;
  if (n == "Y10") return V4l2PixelFormat::Y10;
  if (n == "Y16") return V4l2PixelFormat::Y16;
  if (n == "YUYV") return V4l2PixelFormat::Yuyv;
  if (n == "MJPEG" || n == "MJPG") return V4l2PixelFormat::Mjpeg;
  throw ConfigError("pixel format '" + name + "' is not one of GREY, Y10, Y16, YUYV, MJPEG");
}

std::uint32_t v4l2FourCc(V4l2PixelFormat format) {
  switch (format) {
    case V4l2PixelFormat::Grey:
      return V4L2_PIX_FMT_GREY;
    case V4l2PixelFormat::Y10:
      return V4L2_PIX_FMT_Y10;
    case V4l2PixelFormat::Y16:
      return V4L2_PIX_FMT_Y16;
    case V4l2PixelFormat::Yuyv:
      return V4L2_PIX_FMT_YUYV;
    case V4l2PixelFormat::Mjpeg:
      return V4L2_PIX_FMT_MJPEG;
  }
  return 0;
}

std::string fourCcToString(std::uint32_t fourcc) {
  std::string s(4, ' ');
  for (int i = 0; i < 4; ++i) {
    const auto c = static_cast<unsigned char>((fourcc >> (8 * i)) & 0xFFu);
    s[static_cast<std::size_t>(i)] = std::isprint(c) ? static_cast<char>(c) : '?';
  }
  return s;
}

bool V4l2FrameSize::contains(int width, int height) const {
  return width >= min_width && width <= max_width && height >= min_height && height <= max_height &&
         onStep(width, min_width, step_width) && onStep(height, min_height, step_height);
}

void validate(const V4l2Options& o) {
  auto fail = [](const std::string& what) { throw ConfigError("v4l2 option " + what); };
  if (o.device.empty()) fail("device is empty (give a path such as /dev/video0)");
  if (o.formats.empty())
    fail("formats is empty (give at least one of GREY, Y10, Y16, YUYV, MJPEG)");
  if (o.width < 0 || o.height < 0 || o.width > 16384 || o.height > 16384)
    fail("width x height = " + std::to_string(o.width) + "x" + std::to_string(o.height) +
         " is outside 0..16384");
  if ((o.width == 0) != (o.height == 0))
    fail("width and height must be given together (or both 0 for the largest size)");
  if (!std::isfinite(o.fps) || o.fps < 0.0 || o.fps > 1000.0)
    fail("fps = " + fpsText(o.fps) + " is outside 0..1000 (0: the device's rate)");
  if (o.buffer_count < 2 || o.buffer_count > 32)
    fail("buffer_count = " + std::to_string(o.buffer_count) + " is outside 2..32");
  if (!std::isfinite(o.exposure_ms) || o.exposure_ms < 0.0 || o.exposure_ms > 10000.0)
    fail("exposure_ms = " + fpsText(o.exposure_ms) + " is outside 0..10000 (0: automatic)");
  if (!std::isfinite(o.gain) || o.gain > 1e6)
    fail("gain = " + fpsText(o.gain) + " is not a finite value (negative: automatic)");
  if (o.poll_timeout_ms < 1 || o.poll_timeout_ms > 600000)
    fail("poll_timeout_ms = " + std::to_string(o.poll_timeout_ms) + " is outside 1..600000");
}

V4l2Mode chooseV4l2Mode(const std::vector<V4l2FormatDescription>& offered,
                        const V4l2Options& options) {
  const bool any_size = options.width == 0 && options.height == 0;
  for (V4l2PixelFormat wanted : options.formats) {
    for (const V4l2FormatDescription& d : offered) {
      if (!d.supported || d.format != wanted) continue;
      V4l2Mode mode;
      mode.format = wanted;
      if (d.sizes.empty()) {  // the driver does not enumerate sizes: S_FMT will tell
        mode.width = options.width;
        mode.height = options.height;
        mode.fps = options.fps;
        return mode;
      }
      const V4l2FrameSize* best = nullptr;
      for (const V4l2FrameSize& s : d.sizes) {
        if (any_size) {
          if (best == nullptr || static_cast<long long>(s.max_width) * s.max_height >
                                     static_cast<long long>(best->max_width) * best->max_height)
            best = &s;
        } else if (s.contains(options.width, options.height)) {
          best = &s;
          break;
        }
      }
      if (best == nullptr) continue;
      mode.width = any_size ? best->max_width : options.width;
      mode.height = any_size ? best->max_height : options.height;
      mode.fps = chooseFps(*best, options.fps);
      return mode;
    }
  }
  const std::string size =
      any_size ? std::string()
               : " at " + std::to_string(options.width) + "x" + std::to_string(options.height);
  throw DeviceError(options.device + ": format not supported: the device offers no " +
                    preferenceList(options.formats) + size + "; it offers:\n" +
                    describeV4l2Formats(offered) +
                    "choose one of these with the pixel format, width and height options");
}

std::string describeV4l2Formats(const std::vector<V4l2FormatDescription>& formats) {
  if (formats.empty()) return "  (no capture formats)\n";
  std::string s;
  for (const V4l2FormatDescription& d : formats) {
    s += "  " + (d.supported ? std::string(toString(d.format)) : fourCcToString(d.fourcc)) + " (" +
         d.description + ")" + (d.supported ? "" : " [not supported by ldsm]") + ":";
    if (d.sizes.empty()) s += " sizes not listed by the driver";
    for (std::size_t i = 0; i < d.sizes.size(); ++i) {
      const V4l2FrameSize& z = d.sizes[i];
      s += i == 0 ? " " : ", ";
      if (z.isDiscrete()) {
        s += std::to_string(z.max_width) + "x" + std::to_string(z.max_height);
      } else {
        s += std::to_string(z.min_width) + "x" + std::to_string(z.min_height) + " to " +
             std::to_string(z.max_width) + "x" + std::to_string(z.max_height);
      }
      if (!z.fps.empty()) {
        s += " @";
        for (double f : z.fps) s += " " + fpsText(f);
        s += " fps";
      } else if (z.max_fps > 0.0) {
        s += " @ " + fpsText(z.min_fps) + "-" + fpsText(z.max_fps) + " fps";
      }
    }
    s += "\n";
  }
  return s;
}

}  // namespace ldsm::drivers
