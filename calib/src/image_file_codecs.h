// Internals of the image file module (calib/src/image_file*.cpp): the per-format decoders and
// the sample conversions they share.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "ldsm/calib/image_file.h"
#include "ldsm/image.h"

namespace ldsm::calib::detail {

/// Throws ldsm::InputError "<where>: cannot decode image: <what>".
[[noreturn]] void throwDecodeError(const std::string& where, const std::string& what);

/// Throws when width or height is not in 1..kMaxImageDimension.
void checkImageSize(const std::string& where, long long width, long long height);

/// 16-bit sample to 8 bits: the high byte (inverse of the 8 -> 16 bit expansion v * 257).
inline std::uint8_t scale16To8(std::uint32_t v) {
  return static_cast<std::uint8_t>(v >> 8);
}

/// BT.601 luma of a colour sample triple, in the samples' own range (8 or 16 bits).
inline std::uint32_t lumaOf(std::uint32_t r, std::uint32_t g, std::uint32_t b) {
  return (4899u * r + 9617u * g + 1868u * b + 8192u) >> 14;
}

/// Converts one decoded row to grey samples of T (uint8_t or uint16_t). `src` holds `width`
/// pixels of `channels` (1 or 3) interleaved samples of `bit_depth` 8 or 16 (native-endian).
template <typename T>
void rowToGrey(const unsigned char* src, int bit_depth, int channels, int width, T* dst);

/// Decoders of one format each; the data's signature has been checked by the caller.
template <typename T>
ImageFileInfo decodePng(const unsigned char* data, std::size_t size, const std::string& where,
                        Image<T>& out);
template <typename T>
ImageFileInfo decodeJpeg(const unsigned char* data, std::size_t size, const std::string& where,
                         Image<T>& out);
template <typename T>
ImageFileInfo decodePnm(const unsigned char* data, std::size_t size, const std::string& where,
                        Image<T>& out);

}  // namespace ldsm::calib::detail
