#include "v4l2/v4l2_convert.h"

#include <cstdint>
#include <cstring>

#include "ldsm/calib/image_file.h"
#include "ldsm/error.h"

namespace ldsm::drivers::v4l2 {
namespace {

template <int Shift>
void wordsToGrey(const unsigned char* src, int width, std::uint8_t* dst) {
  for (int x = 0; x < width; ++x) {
    const unsigned v =
        static_cast<unsigned>(src[2 * x]) | (static_cast<unsigned>(src[2 * x + 1]) << 8);
    const unsigned g = v >> Shift;
    dst[x] = static_cast<std::uint8_t>(g > 255u ? 255u : g);  // Y10 words may carry stray bits
  }
}

}  // namespace

int bytesPerPixel(V4l2PixelFormat format) {
  switch (format) {
    case V4l2PixelFormat::Grey:
      return 1;
    case V4l2PixelFormat::Y10:
    case V4l2PixelFormat::Y16:
    case V4l2PixelFormat::Yuyv:
      return 2;
    case V4l2PixelFormat::Mjpeg:
      return 0;
  }
  return 0;
}

bool convertToGrey(const FrameLayout& layout, const unsigned char* data, std::size_t size,
                   ImageU8& out, std::string& problem) {
  const int w = layout.width;
  const int h = layout.height;
  if (layout.format == V4l2PixelFormat::Mjpeg) {
    try {
      calib::decodeImage(data, size, "MJPEG frame", out);
    } catch (const InputError& e) {
      problem = e.what();
      return false;
    }
    if (out.width() != w || out.height() != h) {
      problem = "MJPEG frame of " + std::to_string(out.width()) + "x" +
                std::to_string(out.height()) + " instead of " + std::to_string(w) + "x" +
                std::to_string(h);
      return false;
    }
    return true;
  }

  const std::size_t row_bytes = static_cast<std::size_t>(w) * bytesPerPixel(layout.format);
  const std::size_t stride = layout.bytes_per_line >= row_bytes ? layout.bytes_per_line : row_bytes;
  const std::size_t needed = stride * static_cast<std::size_t>(h - 1) + row_bytes;
  if (size < needed) {
    problem =
        "truncated frame: " + std::to_string(size) + " bytes instead of " + std::to_string(needed);
    return false;
  }
  out.resize(w, h);
  for (int y = 0; y < h; ++y) {
    const unsigned char* src = data + stride * static_cast<std::size_t>(y);
    std::uint8_t* dst = out.row(y);
    switch (layout.format) {
      case V4l2PixelFormat::Grey:
        std::memcpy(dst, src, static_cast<std::size_t>(w));
        break;
      case V4l2PixelFormat::Y10:
        wordsToGrey<2>(src, w, dst);
        break;
      case V4l2PixelFormat::Y16:
        wordsToGrey<8>(src, w, dst);
        break;
      case V4l2PixelFormat::Yuyv:
        for (int x = 0; x < w; ++x) dst[x] = src[2 * x];
        break;
      case V4l2PixelFormat::Mjpeg:
        break;
    }
  }
  return true;
}

}  // namespace ldsm::drivers::v4l2
