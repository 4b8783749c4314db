// libcamera pixel formats and their conversion to 8-bit grey, and the option -> control mapping.
// No libcamera header here: the formats are DRM four-character codes and modifiers.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "ldsm/drivers/libcamera_source.h"
#include "ldsm/error.h"

namespace ldsm::drivers {
namespace {

constexpr std::uint32_t fourcc(char a, char b, char c, char d) {
  return static_cast<std::uint32_t>(a) | (static_cast<std::uint32_t>(b) << 8) |
         (static_cast<std::uint32_t>(c) << 16) | (static_cast<std::uint32_t>(d) << 24);
}
/// fourcc_mod_code(MIPI, 1): MIPI CSI-2 packed (vendor 11 in the top byte).
constexpr std::uint64_t kCsi2Packed = (std::uint64_t{11} << 56) | 1u;

struct FormatEntry {
  LibcameraPixelFormat format;
  const char* name;
  std::uint32_t fourcc;
  std::uint64_t modifier;
};

constexpr FormatEntry kFormats[] = {
    {LibcameraPixelFormat::R8, "R8", fourcc('R', '8', ' ', ' '), 0},
    {LibcameraPixelFormat::R10, "R10", fourcc('R', '1', '0', ' '), 0},
    {LibcameraPixelFormat::R12, "R12", fourcc('R', '1', '2', ' '), 0},
    {LibcameraPixelFormat::R10Csi2p, "R10_CSI2P", fourcc('R', '1', '0', ' '), kCsi2Packed},
    {LibcameraPixelFormat::R12Csi2p, "R12_CSI2P", fourcc('R', '1', '2', ' '), kCsi2Packed},
    {LibcameraPixelFormat::Yuyv, "YUYV", fourcc('Y', 'U', 'Y', 'V'), 0},
    {LibcameraPixelFormat::Uyvy, "UYVY", fourcc('U', 'Y', 'V', 'Y'), 0},
    {LibcameraPixelFormat::Nv12, "NV12", fourcc('N', 'V', '1', '2'), 0},
    {LibcameraPixelFormat::Nv21, "NV21", fourcc('N', 'V', '2', '1'), 0},
    {LibcameraPixelFormat::Yuv420, "YUV420", fourcc('Y', 'U', '1', '2'), 0},
};

std::string upper(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
  return s;
}

/// Bytes of one row of `width` pixels (the minimum stride).
std::size_t rowBytes(LibcameraPixelFormat f, int width) {
  const auto w = static_cast<std::size_t>(width);
  switch (f) {
    case LibcameraPixelFormat::R10:
    case LibcameraPixelFormat::R12:
    case LibcameraPixelFormat::Yuyv:
    case LibcameraPixelFormat::Uyvy:
      return 2 * w;
    case LibcameraPixelFormat::R10Csi2p:
      return (w + 3) / 4 * 5;
    case LibcameraPixelFormat::R12Csi2p:
      return (w + 1) / 2 * 3;
    default:
      return w;
  }
}

template <int Shift>
void wordsToGrey(const unsigned char* src, int width, std::uint8_t* dst) {
  for (int x = 0; x < width; ++x) {
    const unsigned v =
        static_cast<unsigned>(src[2 * x]) | (static_cast<unsigned>(src[2 * x + 1]) << 8);
    const unsigned g = v >> Shift;
    dst[x] = static_cast<std::uint8_t>(g > 255u ? 255u : g);
  }
}

}  // namespace

const char* toString(LibcameraPixelFormat format) {
  for (const FormatEntry& e : kFormats)
    if (e.format == format) return e.name;
  return "unsupported";
}

LibcameraPixelFormat parseLibcameraPixelFormat(const std::string& name) {
  const std::string n = upper(name);
  for (const FormatEntry& e : kFormats)
    if (n == e.name) return e.format;
  std::string names;
  for (const FormatEntry& e : kFormats) names += std::string(names.empty() ? "" : ", ") + e.name;
  throw ConfigError("libcamera pixel format '" + name + "' is not one of " + names);
}

LibcameraFourCc libcameraFourCc(LibcameraPixelFormat format) {
  for (const FormatEntry& e : kFormats)
    if (e.format == format) return {e.fourcc, e.modifier};
  return {};
}

LibcameraPixelFormat classifyLibcameraFormat(std::uint32_t code, std::uint64_t modifier) {
  for (const FormatEntry& e : kFormats)
    if (e.fourcc == code && e.modifier == modifier) return e.format;
  return LibcameraPixelFormat::Unsupported;
}

bool convertLibcameraPlane(LibcameraPixelFormat format, const unsigned char* data, std::size_t size,
                           int width, int height, int stride, ImageU8& out, std::string& problem) {
  if (format == LibcameraPixelFormat::Unsupported) {
    problem = "unsupported pixel format";
    return false;
  }
  if (width <= 0 || height <= 0 || data == nullptr) {
    problem = "empty frame";
    return false;
  }
  const std::size_t row = rowBytes(format, width);
  const std::size_t pitch = stride > 0 && static_cast<std::size_t>(stride) >= row
                                ? static_cast<std::size_t>(stride)
                                : row;
  const std::size_t needed = pitch * static_cast<std::size_t>(height - 1) + row;
  if (size < needed) {
    problem =
        "truncated frame: " + std::to_string(size) + " bytes instead of " + std::to_string(needed);
    return false;
  }
  out.resize(width, height);
  for (int y = 0; y < height; ++y) {
    const unsigned char* src = data + pitch * static_cast<std::size_t>(y);
    std::uint8_t* dst = out.row(y);
    switch (format) {
      case LibcameraPixelFormat::R10:
        wordsToGrey<2>(src, width, dst);
        break;
      case LibcameraPixelFormat::R12:
        wordsToGrey<4>(src, width, dst);
        break;
      case LibcameraPixelFormat::R10Csi2p:
        for (int x = 0; x < width; ++x) dst[x] = src[(x / 4) * 5 + x % 4];
        break;
      case LibcameraPixelFormat::R12Csi2p:
        for (int x = 0; x < width; ++x) dst[x] = src[(x / 2) * 3 + x % 2];
        break;
      case LibcameraPixelFormat::Yuyv:
        for (int x = 0; x < width; ++x) dst[x] = src[2 * x];
        break;
      case LibcameraPixelFormat::Uyvy:
        for (int x = 0; x < width; ++x) dst[x] = src[2 * x + 1];
        break;
      default:  // R8 and the luma plane of NV12, NV21, YUV420
        std::memcpy(dst, src, static_cast<std::size_t>(width));
    }
  }
  return true;
}

void validate(const LibcameraOptions& o) {
  auto fail = [](const std::string& what) { throw ConfigError("libcamera option " + what); };
  auto text = [](double v) { return std::to_string(v); };
  if (o.formats.empty()) fail("formats is empty");
  for (LibcameraPixelFormat f : o.formats)
    if (f == LibcameraPixelFormat::Unsupported) fail("formats lists an unsupported format");
  if (o.width < 0 || o.height < 0 || o.width > 16384 || o.height > 16384)
    fail("width x height = " + std::to_string(o.width) + "x" + std::to_string(o.height) +
         " is outside 0..16384");
  if ((o.width == 0) != (o.height == 0)) fail("width and height must be given together");
  if (!std::isfinite(o.fps) || o.fps < 0.0 || o.fps > 1000.0)
    fail("fps = " + text(o.fps) + " is outside 0..1000");
  if (o.buffer_count < 2 || o.buffer_count > 32)
    fail("buffer_count = " + std::to_string(o.buffer_count) + " is outside 2..32");
  if (!std::isfinite(o.exposure_ms) || o.exposure_ms < 0.0 || o.exposure_ms > 10000.0)
    fail("exposure_ms = " + text(o.exposure_ms) + " is outside 0..10000 (0: automatic)");
  if (!std::isfinite(o.analogue_gain) || (o.analogue_gain != 0.0 && o.analogue_gain < 1.0) ||
      o.analogue_gain > 1000.0)
    fail("analogue_gain = " + text(o.analogue_gain) + " is neither 0 (automatic) nor in 1..1000");
  if (o.timeout_ms < 1 || o.timeout_ms > 600000)
    fail("timeout_ms = " + std::to_string(o.timeout_ms) + " is outside 1..600000");
}

LibcameraControls mapLibcameraControls(const LibcameraOptions& o) {
  LibcameraControls c;
  if (o.exposure_ms > 0.0)
    c.exposure_time_us = static_cast<std::int32_t>(std::lround(o.exposure_ms * 1000.0));
  if (o.analogue_gain > 0.0) c.analogue_gain = static_cast<float>(o.analogue_gain);
  c.ae_enable = !(o.lock_auto_exposure || c.exposure_time_us > 0 || c.analogue_gain > 0.0f);
  if (o.fps > 0.0) c.frame_duration_us = std::llround(1e6 / o.fps);
  return c;
}

double exposureMsFromLibcamera(std::int64_t exposure_time_us) {
  return exposure_time_us > 0 ? static_cast<double>(exposure_time_us) / 1000.0
                              : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace ldsm::drivers
