// Conversion of one captured V4L2 frame to 8-bit grey.
#pragma once

#include <cstddef>
#include <string>

#include "ldsm/drivers/v4l2_source.h"
#include "ldsm/image.h"

namespace ldsm::drivers::v4l2 {

/// Layout of the captured frames (from VIDIOC_S_FMT).
struct FrameLayout {
  V4l2PixelFormat format = V4l2PixelFormat::Grey;
  int width = 0;
  int height = 0;
  std::size_t bytes_per_line = 0;  ///< row stride in bytes (uncompressed formats)
};

/// Bytes per pixel of an uncompressed format (0 for MJPEG).
int bytesPerPixel(V4l2PixelFormat format);

/// Converts `size` bytes of `data` into `out` (resized to width x height; no allocation when its
/// capacity suffices, except inside the JPEG decoder). GREY is copied, Y10 shifted right by 2,
/// Y16 by 8 (16-bit samples little-endian), YUYV keeps the Y bytes, MJPEG is decoded to luma
/// with libjpeg. Returns false, with a reason in `problem`, for a frame that cannot be converted:
/// fewer bytes than the layout needs, or JPEG data that does not decode to the expected size.
bool convertToGrey(const FrameLayout& layout, const unsigned char* data, std::size_t size,
                   ImageU8& out, std::string& problem);

}  // namespace ldsm::drivers::v4l2
