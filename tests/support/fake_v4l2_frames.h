// The frames of the fake V4L2 camera (fake_v4l2_kernel.h): a known 8-bit pattern per frame,
// laid out in the camera's pixel format (GREY, Y10, Y16, YUYV with their extra bits and chroma
// set to noise, MJPEG encoded with OpenCV, RGB24 as an unsupported format), rows padded with
// 0xEE up to bytes_per_line so that a stride mistake shows.
#pragma once

#include <linux/videodev2.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <utility>
#include <vector>

namespace ldsm::test {

/// The 8-bit grey value of pixel (x, y) in frame n of the fake camera.
inline std::uint8_t fakePixel(std::int64_t n, int x, int y) {
  return static_cast<std::uint8_t>((x + 2 * y + 7 * n) & 0xFF);
}

/// Exposure (ms) the fake reports for frame n in automatic exposure mode.
inline double fakeAutoExposureMs(std::int64_t n) {
  return 0.1 * static_cast<double>(100 + n % 50);
}

struct FakeFormat {
  std::uint32_t fourcc = V4L2_PIX_FMT_GREY;
  std::string description;
  std::vector<std::pair<int, int>> sizes;  ///< discrete sizes
  std::vector<int> fps;                    ///< discrete rates, for every size
};

/// GREY, Y16, Y10, YUYV, MJPEG and an unsupported RGB24, at 64x48 (and 32x24).
inline std::vector<FakeFormat> fakeDefaultFormats() {
  return {{V4L2_PIX_FMT_GREY, "8-bit Greyscale", {{64, 48}, {32, 24}}, {30, 15}},
          {V4L2_PIX_FMT_Y16, "16-bit Greyscale", {{64, 48}}, {30}},
          {V4L2_PIX_FMT_Y10, "10-bit Greyscale", {{64, 48}}, {30}},
          {V4L2_PIX_FMT_YUYV, "YUYV 4:2:2", {{64, 48}, {32, 24}}, {30, 15}},
          {V4L2_PIX_FMT_MJPEG, "Motion-JPEG", {{64, 48}}, {30}},
          {V4L2_PIX_FMT_RGB24, "24-bit RGB 8-8-8", {{64, 48}}, {30}}};
}

inline bool fakeUncompressed(std::uint32_t fourcc) {
  return fourcc != V4L2_PIX_FMT_MJPEG && fourcc != V4L2_PIX_FMT_JPEG;
}

inline int fakeBytesPerPixel(std::uint32_t fourcc) {
  return fourcc == V4L2_PIX_FMT_GREY ? 1 : fourcc == V4L2_PIX_FMT_RGB24 ? 3 : 2;
}

/// Writes frame n into `data` (its size is the buffer length) and returns the bytes used.
inline std::size_t fillFakeFrame(std::uint32_t fourcc, int width, int height,
                                 std::size_t bytes_per_line, std::int64_t n, int jpeg_quality,
                                 std::vector<unsigned char>& data) {
  if (!fakeUncompressed(fourcc)) {
    cv::Mat grey(height, width, CV_8UC1);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) grey.at<std::uint8_t>(y, x) = fakePixel(n, x, y);
    std::vector<unsigned char> jpeg;
    cv::imencode(".jpg", grey, jpeg, {cv::IMWRITE_JPEG_QUALITY, jpeg_quality});
    const std::size_t used = std::min(jpeg.size(), data.size());
    std::copy(jpeg.begin(), jpeg.begin() + static_cast<std::ptrdiff_t>(used), data.begin());
    return used;
  }
  std::fill(data.begin(), data.end(), 0xEE);
  const int bpp = fakeBytesPerPixel(fourcc);
  for (int y = 0; y < height; ++y) {
    unsigned char* row = data.data() + static_cast<std::size_t>(y) * bytes_per_line;
    for (int x = 0; x < width; ++x) {
      const unsigned g = fakePixel(n, x, y);
      switch (fourcc) {
        case V4L2_PIX_FMT_GREY:
          row[x] = static_cast<unsigned char>(g);
          break;
        case V4L2_PIX_FMT_Y10: {  // 10 significant bits, little-endian, low bits vary
          const unsigned v = (g << 2) | static_cast<unsigned>((x + y) & 3);
          row[2 * x] = static_cast<unsigned char>(v & 0xFF);
          row[2 * x + 1] = static_cast<unsigned char>(v >> 8);
          break;
        }
        case V4L2_PIX_FMT_Y16: {
          const unsigned v = (g << 8) | static_cast<unsigned>((x * 37 + y) & 0xFF);
          row[2 * x] = static_cast<unsigned char>(v & 0xFF);
          row[2 * x + 1] = static_cast<unsigned char>(v >> 8);
          break;
        }
        case V4L2_PIX_FMT_YUYV:
          row[2 * x] = static_cast<unsigned char>(g);
          row[2 * x + 1] = static_cast<unsigned char>(x % 2 == 0 ? 0x40 : 0xC0);  // U / V
          break;
        default:  // RGB24 and anything else: grey in every channel
          for (int c = 0; c < bpp; ++c) row[bpp * x + c] = static_cast<unsigned char>(g);
      }
    }
  }
  return bytes_per_line * static_cast<std::size_t>(height);
}

}  // namespace ldsm::test
