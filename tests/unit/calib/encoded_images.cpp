// Test image encoders: a PNG assembler over zlib and a JPEG encoder over libjpeg.
#include "encoded_images.h"

#include <zlib.h>

// clang-format off
#include <cstdio>
#include <jpeglib.h>
// clang-format on

#include <cstring>

namespace ldsm::test {
namespace {

void put32(Bytes& out, std::uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) out.push_back(static_cast<unsigned char>(v >> s));
}

void appendChunk(Bytes& png, const char* type, const Bytes& data) {
  put32(png, static_cast<std::uint32_t>(data.size()));
  const std::size_t start = png.size();
  png.insert(png.end(), type, type + 4);
  png.insert(png.end(), data.begin(), data.end());
  const uLong crc = crc32(0L, png.data() + start, static_cast<uInt>(png.size() - start));
  put32(png, static_cast<std::uint32_t>(crc));
}

/// One filtered scanline (filter type 0) of the pixels x0, x0 + dx, ... of row y.
void appendScanline(const PngSpec& s, int y, int x0, int dx, Bytes& raw) {
  const int channels = pngChannels(s.color_type);
  raw.push_back(0);
  unsigned bits = 0;
  int nbits = 0;
  for (int x = x0; x < s.width; x += dx) {
    for (int c = 0; c < channels; ++c) {
      const std::uint16_t v = s.samples[(static_cast<std::size_t>(y) * s.width + x) * channels + c];
      if (s.bit_depth == 16) {
        raw.push_back(static_cast<unsigned char>(v >> 8));
        raw.push_back(static_cast<unsigned char>(v & 0xff));
      } else if (s.bit_depth == 8) {
        raw.push_back(static_cast<unsigned char>(v));
      } else {
        bits = (bits << s.bit_depth) | v;
        nbits += s.bit_depth;
        if (nbits == 8) {
          raw.push_back(static_cast<unsigned char>(bits));
          bits = 0;
          nbits = 0;
        }
      }
    }
  }
  if (nbits > 0) raw.push_back(static_cast<unsigned char>(bits << (8 - nbits)));
}

}  // namespace

int pngChannels(int color_type) {
  switch (color_type) {
    case 2:
      return 3;
    case 4:
      return 2;
    case 6:
      return 4;
    default:
      return 1;
  }
}

Bytes buildPng(const PngSpec& s) {
  Bytes png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  Bytes ihdr;
  put32(ihdr, static_cast<std::uint32_t>(s.width));
  put32(ihdr, static_cast<std::uint32_t>(s.height));
  ihdr.push_back(static_cast<unsigned char>(s.bit_depth));
  ihdr.push_back(static_cast<unsigned char>(s.color_type));
  ihdr.push_back(0);
  ihdr.push_back(0);
  ihdr.push_back(s.interlaced ? 1 : 0);
  appendChunk(png, "IHDR", ihdr);
  if (!s.palette.empty()) {
    Bytes plte;
    for (const auto& rgb : s.palette) plte.insert(plte.end(), rgb.begin(), rgb.end());
    appendChunk(png, "PLTE", plte);
  }
  if (!s.transparency.empty())
    appendChunk(png, "tRNS", Bytes(s.transparency.begin(), s.transparency.end()));
  Bytes raw;
  if (!s.interlaced) {
    for (int y = 0; y < s.height; ++y) appendScanline(s, y, 0, 1, raw);
  } else {
    constexpr int kPass[7][4] = {{0, 0, 8, 8}, {4, 0, 8, 8}, {0, 4, 4, 8}, {2, 0, 4, 4},
                                 {0, 2, 2, 4}, {1, 0, 2, 2}, {0, 1, 1, 2}};
    for (const auto& p : kPass) {
      if (p[0] >= s.width) continue;  // empty pass: no scanlines at all
      for (int y = p[1]; y < s.height; y += p[3]) appendScanline(s, y, p[0], p[2], raw);
    }
  }
  uLongf packed_size = compressBound(static_cast<uLong>(raw.size()));
  Bytes packed(packed_size);
  EXPECT_EQ(compress2(packed.data(), &packed_size, raw.data(), static_cast<uLong>(raw.size()), 6),
            Z_OK);
  packed.resize(packed_size);
  appendChunk(png, "IDAT", packed);
  appendChunk(png, "IEND", {});
  return png;
}

std::size_t pngChunkData(const Bytes& png, const char* type) {
  std::size_t pos = 8;
  while (pos + 8 <= png.size()) {
    const std::uint32_t length = static_cast<std::uint32_t>(png[pos]) << 24 |
                                 static_cast<std::uint32_t>(png[pos + 1]) << 16 |
                                 static_cast<std::uint32_t>(png[pos + 2]) << 8 | png[pos + 3];
    if (std::memcmp(png.data() + pos + 4, type, 4) == 0) return pos + 8;
    pos += 12 + length;
  }
  ADD_FAILURE() << "no " << type << " chunk";
  return 0;
}

void patchPngChunk(Bytes& png, const char* type, std::size_t offset, unsigned char value) {
  const std::size_t data = pngChunkData(png, type);
  const std::uint32_t length = static_cast<std::uint32_t>(png[data - 8]) << 24 |
                               static_cast<std::uint32_t>(png[data - 7]) << 16 |
                               static_cast<std::uint32_t>(png[data - 6]) << 8 | png[data - 5];
  ASSERT_LT(offset, length);
  png[data + offset] = value;
  const uLong crc = crc32(0L, png.data() + data - 4, static_cast<uInt>(length + 4));
  for (int k = 0; k < 4; ++k)
    png[data + length + k] = static_cast<unsigned char>(crc >> (24 - 8 * k));
}

Bytes encodeJpeg(const std::vector<std::uint8_t>& samples, int width, int height, int components,
                 int stored, int quality) {
  jpeg_compress_struct cinfo;
  jpeg_error_mgr err;
  cinfo.err = jpeg_std_error(&err);  // a failure exits the test process: acceptable here
  jpeg_create_compress(&cinfo);
  unsigned char* buffer = nullptr;
  unsigned long size = 0;
  jpeg_mem_dest(&cinfo, &buffer, &size);
  cinfo.image_width = static_cast<JDIMENSION>(width);
  cinfo.image_height = static_cast<JDIMENSION>(height);
  cinfo.input_components = components;
  cinfo.in_color_space = components == 1 ? JCS_GRAYSCALE : components == 3 ? JCS_RGB : JCS_CMYK;
  jpeg_set_defaults(&cinfo);
  jpeg_set_colorspace(&cinfo, static_cast<J_COLOR_SPACE>(stored));
  for (int c = 0; c < cinfo.num_components; ++c) {
    cinfo.comp_info[c].h_samp_factor = 1;
    cinfo.comp_info[c].v_samp_factor = 1;
  }
  jpeg_set_quality(&cinfo, quality, TRUE);
  jpeg_start_compress(&cinfo, TRUE);
  while (cinfo.next_scanline < cinfo.image_height) {
    JSAMPROW row = const_cast<JSAMPROW>(samples.data()) +
                   static_cast<std::size_t>(cinfo.next_scanline) * width * components;
    jpeg_write_scanlines(&cinfo, &row, 1);
  }
  jpeg_finish_compress(&cinfo);
  jpeg_destroy_compress(&cinfo);
  Bytes out(buffer, buffer + size);
  std::free(buffer);
  return out;
}

}  // namespace ldsm::test
