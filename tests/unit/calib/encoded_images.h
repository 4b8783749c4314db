// Encoded test images made independently of the decoders under test: PNG files assembled chunk
// by chunk here (zlib for the compressed data, so any colour type, bit depth, palette or
// interlacing can be produced, and broken on purpose), JPEG files from libjpeg's compressor.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "ldsm/error.h"

namespace ldsm::test {

using Bytes = std::vector<unsigned char>;

/// A PNG to assemble. `samples` holds width * height * channels values (row-major, channels
/// interleaved) of `bit_depth` bits; for palette images they are palette indices.
struct PngSpec {
  int width = 0;
  int height = 0;
  int bit_depth = 8;
  int color_type = 0;  ///< 0 grey, 2 RGB, 3 palette, 4 grey + alpha, 6 RGBA
  bool interlaced = false;
  std::vector<std::uint16_t> samples;
  std::vector<std::array<std::uint8_t, 3>> palette;  ///< PLTE (palette images)
  std::vector<std::uint8_t> transparency;            ///< tRNS, when not empty
};

/// Channels of a PNG colour type.
int pngChannels(int color_type);

/// The PNG file of `spec`.
Bytes buildPng(const PngSpec& spec);

/// Offset of the first byte of the data of the first chunk of `type` in a PNG file.
std::size_t pngChunkData(const Bytes& png, const char* type);

/// Sets byte `offset` of the data of the first chunk of `type` and fixes the chunk's CRC, so
/// that the file is consistent but says something else.
void patchPngChunk(Bytes& png, const char* type, std::size_t offset, unsigned char value);

/// A JPEG file from 8-bit samples of `components` (1 grey, 3 RGB, 4 CMYK) interleaved channels,
/// stored in colour space `stored` (as libjpeg's J_COLOR_SPACE: 1 grey, 2 RGB, 3 YCbCr,
/// 4 CMYK), at `quality`, with every component at full resolution.
Bytes encodeJpeg(const std::vector<std::uint8_t>& samples, int width, int height, int components,
                 int stored, int quality);

/// The what() of the ldsm::InputError thrown by f, or "" (a failure is recorded) when none is.
template <typename F>
std::string inputErrorOf(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected ldsm::InputError, got: " << e.what();
    return {};
  }
  ADD_FAILURE() << "expected ldsm::InputError, nothing thrown";
  return {};
}

}  // namespace ldsm::test
