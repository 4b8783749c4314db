#include "ldsm/drivers/place_ground_truth.h"

#include <cstring>

#include <memory>

#include "ldsm/calib/image_file.h"
#include "ldsm/drivers/dataset_source.h"
#include "ldsm/error.h"
#include "ldsm/image.h"

namespace ldsm::drivers {
namespace {

std::uint32_t u32(const unsigned char* p) {
  return static_cast<std::uint32_t>(p[0]) | static_cast<std::uint32_t>(p[1]) << 8 |
         static_cast<std::uint32_t>(p[2]) << 16 | static_cast<std::uint32_t>(p[3]) << 24;
}
std::uint16_t u16(const unsigned char* p) {
  return static_cast<std::uint16_t>(p[0] | p[1] << 8);
}

/// Decodes an uncompressed 8-bit palette or 24-bit BMP to grey (mean of B, G, R), top row first.
void decodeBmp(const std::vector<unsigned char>& d, const std::string& path, ImageU8& out) {
  auto fail = [&path](const std::string& what) { throw InputError(path + ": " + what); };
  if (d.size() < 54) fail("truncated BMP header");
  const std::uint32_t offset = u32(&d[10]);
  const std::uint32_t dib = u32(&d[14]);
  const auto width = static_cast<std::int32_t>(u32(&d[18]));
  const auto raw_height = static_cast<std::int32_t>(u32(&d[22]));
  const std::uint16_t bpp = u16(&d[28]);
  const std::uint32_t compression = u32(&d[30]);
  if (dib < 40) fail("unsupported BMP header (OS/2 bitmap)");
  if (compression != 0) fail("compressed BMP files are not supported");
  if (bpp != 8 && bpp != 24) {
    fail("BMP with " + std::to_string(bpp) + " bits per pixel (8 or 24 supported)");
  }
  if (width <= 0 || raw_height == 0 || width > 1 << 15 || raw_height > 1 << 15 ||
      raw_height < -(1 << 15)) {
    fail("BMP size " + std::to_string(width) + "x" + std::to_string(raw_height) + " is invalid");
  }
  const int height = raw_height < 0 ? -raw_height : raw_height;
  const std::size_t stride = (static_cast<std::size_t>(width) * bpp / 8 + 3) / 4 * 4;
  if (offset > d.size() || d.size() - offset < stride * static_cast<std::size_t>(height)) {
    fail("truncated BMP pixel data");
  }
  std::uint8_t palette[256];
  if (bpp == 8) {
    std::uint32_t colors = u32(&d[46]);
    if (colors == 0 || colors > 256) colors = 256;
    const std::size_t pal = 14 + static_cast<std::size_t>(dib);
    if (pal + 4 * static_cast<std::size_t>(colors) > offset) fail("truncated BMP palette");
    std::memset(palette, 0, sizeof(palette));
    for (std::uint32_t c = 0; c < colors; ++c) {
      const unsigned char* e = &d[pal + 4 * c];
      palette[c] = static_cast<std::uint8_t>((e[0] + e[1] + e[2]) / 3);
    }
  }
  out.resize(width, height);
  for (int y = 0; y < height; ++y) {
    const int file_row = raw_height > 0 ? height - 1 - y : y;
    const unsigned char* row = &d[offset + stride * static_cast<std::size_t>(file_row)];
    std::uint8_t* o = out.row(y);
    for (int x = 0; x < width; ++x) {
      o[x] = bpp == 8
                 ? palette[row[x]]
                 : static_cast<std::uint8_t>((row[3 * x] + row[3 * x + 1] + row[3 * x + 2]) / 3);
    }
  }
}

}  // namespace

std::vector<std::vector<std::uint8_t>> readPlaceGroundTruth(const std::string& path) {
  std::vector<unsigned char> bytes;
  calib::readFileBytes(path, bytes);
  ImageU8 image;
  if (bytes.size() >= 2 && bytes[0] == 'B' && bytes[1] == 'M') {
    decodeBmp(bytes, path, image);
  } else {
    calib::decodeImage(bytes.data(), bytes.size(), path, image);
  }
  if (image.width() != image.height()) {
    throw InputError(path + ": a place ground truth must be square (got " +
                     std::to_string(image.width()) + "x" + std::to_string(image.height()) + ")");
  }
  const int n = image.width();
  std::vector<std::vector<std::uint8_t>> gt(static_cast<std::size_t>(n),
                                            std::vector<std::uint8_t>(static_cast<std::size_t>(n)));
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j)
      gt[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] = image(j, i) > 127 ? 1 : 0;
  }
  return gt;
}

PlaceDataset readPlaceDataset(const std::string& dir, const std::string& ground_truth_file) {
  PlaceDataset d;
  const std::string gt_path = dir + "/" + ground_truth_file;
  d.same_place = readPlaceGroundTruth(gt_path);
  std::unique_ptr<FrameSource> source = openDataset(dir);
  Frame frame;
  while (source->next(frame)) d.images.push_back(frame.image);
  if (d.images.size() != d.same_place.size()) {
    throw InputError(gt_path + ": ground truth for " + std::to_string(d.same_place.size()) +
                     " images, but " + dir + " holds " + std::to_string(d.images.size()));
  }
  return d;
}

}  // namespace ldsm::drivers
