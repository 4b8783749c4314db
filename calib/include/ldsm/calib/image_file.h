// Image files without OpenCV imgcodecs: decoding PNG (libpng), JPEG (libjpeg-turbo) and binary
// PGM/PPM to 8- or 16-bit grey ldsm images, from a file or a memory buffer (a zip entry), and
// encoding 8/16-bit grey and 8-bit RGB PNG files.
//
// Conversions to grey, identical for every format:
//  * colour: Y = 0.299 R + 0.587 G + 0.114 B (ITU-R BT.601, fixed point, rounded), the luma of
//    JPEG; alpha is ignored; palette images are expanded to their colours first;
//  * 8 -> 16 bits: v * 257 (0..255 onto 0..65535); 16 -> 8 bits: the high byte, v / 256
//    rounded down (its exact inverse, and what libpng and OpenCV's grey reading do);
//  * grey of 1, 2 or 4 bits (PNG) and PNM maxval other than 255/65535: scaled to the full range
//    (to 8 bits directly when maxval < 256, else to 16 bits first).
//
// Decoding into an Image reuses its buffer: no allocation when the capacity suffices.
// Every failure throws ldsm::InputError "<where>: cannot decode image: <what is wrong>".
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "ldsm/image.h"

namespace ldsm::calib {

/// Encoded image formats recognised from the first bytes of the data.
enum class ImageFileFormat { Unknown, Png, Jpeg, Pnm };

/// Name of a format ("PNG", "JPEG", "PNM", "unknown").
const char* toString(ImageFileFormat format);

/// What the encoded image holds, before any conversion.
struct ImageFileInfo {
  ImageFileFormat format = ImageFileFormat::Unknown;
  int width = 0;
  int height = 0;
  int channels = 0;   ///< 1 grey, 2 grey + alpha, 3 colour (and palette), 4 colour + alpha
  int bit_depth = 0;  ///< significant bits per sample in the file (1..16)
};

/// An 8-bit RGB pixel, for colour PNG files (plots).
struct Rgb8 {
  std::uint8_t r = 0;
  std::uint8_t g = 0;
  std::uint8_t b = 0;
};
static_assert(sizeof(Rgb8) == 3, "Rgb8 must be three packed bytes");

/// Largest width or height accepted by the decoders (guards against absurd headers).
inline constexpr int kMaxImageDimension = 1 << 15;

/// The format of encoded data from its signature (Unknown when none matches).
ImageFileFormat detectImageFileFormat(const unsigned char* data, std::size_t size);

/// Reads the whole file `path` into `bytes` (capacity reused). Throws ldsm::InputError
/// "<path>: cannot open ..." / "<path>: read error".
void readFileBytes(const std::string& path, std::vector<unsigned char>& bytes);

/// Decodes an image held in memory to 8-bit grey into `out` (resized only when needed). `where`
/// names the data in error messages (a file, "archive.zip:entry"). Returns the file's properties.
ImageFileInfo decodeImage(const unsigned char* data, std::size_t size, const std::string& where,
                          ImageU8& out);
/// Same, to 16-bit grey.
ImageFileInfo decodeImage(const unsigned char* data, std::size_t size, const std::string& where,
                          ImageU16& out);

/// Reads and decodes the image file `path` to 8-bit grey (errors name `path`).
ImageFileInfo readImage(const std::string& path, ImageU8& out);
/// Same, to 16-bit grey.
ImageFileInfo readImage(const std::string& path, ImageU16& out);

/// PNG encoder settings.
struct PngWriteOptions {
  int compression_level = 3;  ///< zlib level, 0 (none) .. 9 (smallest, slowest)
};

/// Encodes a PNG file in memory: 8-bit grey, 16-bit grey or 8-bit RGB. Throws ldsm::InputError
/// for an empty image or one larger than PNG allows, ldsm::Error when libpng fails.
std::vector<unsigned char> encodePng(ImageView<const std::uint8_t> image,
                                     const PngWriteOptions& options = {});
std::vector<unsigned char> encodePng(ImageView<const std::uint16_t> image,
                                     const PngWriteOptions& options = {});
std::vector<unsigned char> encodePng(ImageView<const Rgb8> image,
                                     const PngWriteOptions& options = {});

/// Encodes and writes a PNG file. Throws as encodePng(), and ldsm::Error
/// "<path>: cannot open for writing ..." / "<path>: write error".
void writePng(const std::string& path, ImageView<const std::uint8_t> image,
              const PngWriteOptions& options = {});
void writePng(const std::string& path, ImageView<const std::uint16_t> image,
              const PngWriteOptions& options = {});
void writePng(const std::string& path, ImageView<const Rgb8> image,
              const PngWriteOptions& options = {});

}  // namespace ldsm::calib
