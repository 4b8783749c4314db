// Image files: format detection, whole-file reading, decoding dispatch and PNG file writing.
#include "ldsm/calib/image_file.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <system_error>

#include "image_file_codecs.h"
#include "ldsm/error.h"

namespace ldsm::calib {
namespace {

bool startsWith(const unsigned char* data, std::size_t size, const char* magic, std::size_t n) {
  return size >= n && std::memcmp(data, magic, n) == 0;
}

/// Name of a well-known format this module does not decode, or nullptr.
const char* unsupportedFormatName(const unsigned char* data, std::size_t size) {
  if (startsWith(data, size, "BM", 2)) return "BMP";
  if (startsWith(data, size, "II*\0", 4) || startsWith(data, size, "MM\0*", 4)) return "TIFF";
  if (startsWith(data, size, "GIF8", 4)) return "GIF";
  if (startsWith(data, size, "RIFF", 4) && size >= 12 && std::memcmp(data + 8, "WEBP", 4) == 0)
    return "WebP";
  return nullptr;
}

template <typename T>
ImageFileInfo decodeAny(const unsigned char* data, std::size_t size, const std::string& where,
                        Image<T>& out) {
  if (data == nullptr || size == 0) detail::throwDecodeError(where, "the file is empty");
  switch (detectImageFileFormat(data, size)) {
    case ImageFileFormat::Png:
      return detail::decodePng(data, size, where, out);
    case ImageFileFormat::Jpeg:
      return detail::decodeJpeg(data, size, where, out);
    case ImageFileFormat::Pnm:
      return detail::decodePnm(data, size, where, out);
    case ImageFileFormat::Unknown:
      break;
  }
  if (const char* name = unsupportedFormatName(data, size))
    detail::throwDecodeError(where, std::string(name) +
                                        " images are not supported (PNG, JPEG and binary "
                                        "PGM/PPM are)");
  detail::throwDecodeError(where, "not a PNG, JPEG or PGM/PPM file");
}

template <typename T>
ImageFileInfo readAny(const std::string& path, Image<T>& out) {
  std::vector<unsigned char> bytes;
  readFileBytes(path, bytes);
  return decodeAny(bytes.data(), bytes.size(), path, out);
}

void writeBytes(const std::string& path, const std::vector<unsigned char>& bytes) {
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  if (!file) throw Error(path + ": cannot open for writing (" + std::strerror(errno) + ")");
  file.write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
  file.close();
  if (!file) throw Error(path + ": write error");
}

}  // namespace

const char* toString(ImageFileFormat format) {
  switch (format) {
    case ImageFileFormat::Png:
      return "PNG";
    case ImageFileFormat::Jpeg:
      return "JPEG";
    case ImageFileFormat::Pnm:
      return "PNM";
    case ImageFileFormat::Unknown:
      break;
  }
  return "unknown";
}

ImageFileFormat detectImageFileFormat(const unsigned char* data, std::size_t size) {
  if (data == nullptr) return ImageFileFormat::Unknown;
  if (startsWith(data, size, "\x89PNG\r\n\x1a\n", 8)) return ImageFileFormat::Png;
  if (startsWith(data, size, "\xff\xd8\xff", 3)) return ImageFileFormat::Jpeg;
  if (size >= 2 && data[0] == 'P' && data[1] >= '1' && data[1] <= '6') return ImageFileFormat::Pnm;
  return ImageFileFormat::Unknown;
}

void readFileBytes(const std::string& path, std::vector<unsigned char>& bytes) {
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(path, ec);
  if (!std::filesystem::exists(status)) throw InputError(path + ": cannot open (no such file)");
  if (std::filesystem::is_directory(status))
    throw InputError(path + ": cannot open: it is a folder, not a file");
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw InputError(path + ": cannot open (" + std::strerror(errno) + ")");
  const std::streamoff size = in.tellg();
  if (size < 0) throw InputError(path + ": read error (not a regular file?)");
  bytes.resize(static_cast<std::size_t>(size));
  in.seekg(0);
  if (size > 0 && !in.read(reinterpret_cast<char*>(bytes.data()), size))
    throw InputError(path + ": read error");
}

ImageFileInfo decodeImage(const unsigned char* data, std::size_t size, const std::string& where,
                          ImageU8& out) {
  return decodeAny(data, size, where, out);
}

ImageFileInfo decodeImage(const unsigned char* data, std::size_t size, const std::string& where,
                          ImageU16& out) {
  return decodeAny(data, size, where, out);
}

ImageFileInfo readImage(const std::string& path, ImageU8& out) {
  return readAny(path, out);
}

ImageFileInfo readImage(const std::string& path, ImageU16& out) {
  return readAny(path, out);
}

void writePng(const std::string& path, ImageView<const std::uint8_t> image,
              const PngWriteOptions& options) {
  writeBytes(path, encodePng(image, options));
}

void writePng(const std::string& path, ImageView<const std::uint16_t> image,
              const PngWriteOptions& options) {
  writeBytes(path, encodePng(image, options));
}

void writePng(const std::string& path, ImageView<const Rgb8> image,
              const PngWriteOptions& options) {
  writeBytes(path, encodePng(image, options));
}

namespace detail {

void throwDecodeError(const std::string& where, const std::string& what) {
  throw InputError(where + ": cannot decode image: " + what);
}

void checkImageSize(const std::string& where, long long width, long long height) {
  if (width <= 0 || height <= 0 || width > kMaxImageDimension || height > kMaxImageDimension)
    throwDecodeError(where, "image size " + std::to_string(width) + " x " + std::to_string(height) +
                                " is outside 1.." + std::to_string(kMaxImageDimension));
}

template <typename T>
void rowToGrey(const unsigned char* src, int bit_depth, int channels, int width, T* dst) {
  constexpr bool kOut16 = sizeof(T) == 2;
  auto sample = [&](int i) -> std::uint32_t {
    if (bit_depth == 8) return src[i];
    std::uint16_t v;
    std::memcpy(&v, src + 2 * static_cast<std::ptrdiff_t>(i), sizeof v);
    return v;
  };
  for (int x = 0; x < width; ++x) {
    const int i = x * channels;
    const std::uint32_t v =
        channels == 1 ? sample(i) : lumaOf(sample(i), sample(i + 1), sample(i + 2));
    if (bit_depth == 16) {
      dst[x] = kOut16 ? static_cast<T>(v) : static_cast<T>(scale16To8(v));
    } else {
      dst[x] = kOut16 ? static_cast<T>(v * 257u) : static_cast<T>(v);
    }
  }
}

template void rowToGrey<std::uint8_t>(const unsigned char*, int, int, int, std::uint8_t*);
template void rowToGrey<std::uint16_t>(const unsigned char*, int, int, int, std::uint16_t*);

}  // namespace detail
}  // namespace ldsm::calib
