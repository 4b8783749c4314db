// PNG decoding and encoding with libpng. libpng reports errors by longjmp: every libpng call is
// made from a small "guarded" function that holds the setjmp and no object with a destructor, so
// the jump never skips a C++ destructor; the caller turns the failure into an exception.
#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <new>
#include <vector>

#include "image_file_codecs.h"
#include "ldsm/error.h"

namespace ldsm::calib {
namespace {

/// Data shared with the libpng callbacks. Trivially destructible.
struct PngIo {
  const unsigned char* data = nullptr;  ///< decoding: the encoded bytes
  std::size_t size = 0;
  std::size_t offset = 0;
  std::vector<unsigned char>* sink = nullptr;  ///< encoding: the output
  char message[256] = {};                      ///< libpng's last error
};

bool hostIsLittleEndian() {
  const std::uint16_t one = 1;
  unsigned char first = 0;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

// ---- libpng callbacks (C frames the longjmp may cross: no destructors) ----------------------

void onPngError(png_structp png, png_const_charp message) {
  auto* io = static_cast<PngIo*>(png_get_error_ptr(png));
  std::snprintf(io->message, sizeof io->message, "%s", message);
  png_longjmp(png, 1);
}

/// Warnings concern ancillary data (a bad sRGB profile, a CRC error in a text chunk): ignored.
void onPngWarning(png_structp, png_const_charp) {}

void readFromMemory(png_structp png, png_bytep dst, png_size_t n) {
  auto* io = static_cast<PngIo*>(png_get_io_ptr(png));
  if (n > io->size - io->offset) png_error(png, "truncated file");
  std::memcpy(dst, io->data + io->offset, n);
  io->offset += n;
}

void writeToVector(png_structp png, png_bytep src, png_size_t n) {
  auto* io = static_cast<PngIo*>(png_get_io_ptr(png));
  bool ok = true;
  try {
    io->sink->insert(io->sink->end(), src, src + n);
  } catch (...) {
    ok = false;
  }
  if (!ok) png_error(png, "out of memory");
}

void flushNothing(png_structp) {}

// ---- guarded libpng steps: false when libpng failed (message in PngIo) ------------------------

bool readInfo(png_structp png, png_infop info) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_read_info(png, info);
  return true;
}

bool setReadTransforms(png_structp png, png_infop info, int* passes) {
  if (setjmp(png_jmpbuf(png))) return false;
  const int color_type = png_get_color_type(png, info);
  if (color_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if (color_type == PNG_COLOR_TYPE_GRAY && png_get_bit_depth(png, info) < 8)
    png_set_expand_gray_1_2_4_to_8(png);
  png_set_strip_alpha(png);  // also the alpha that a palette's tRNS expands to
  if (png_get_bit_depth(png, info) == 16 && hostIsLittleEndian()) png_set_swap(png);
  *passes = png_set_interlace_handling(png);
  png_read_update_info(png, info);
  return true;
}

bool readRow(png_structp png, png_bytep row) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_read_row(png, row, nullptr);
  return true;
}

bool readEnd(png_structp png) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_read_end(png, nullptr);
  return true;
}

bool writeHeader(png_structp png, png_infop info, png_uint_32 width, png_uint_32 height,
                 int bit_depth, int color_type, int compression_level) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_IHDR(png, info, width, height, bit_depth, color_type, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_compression_level(png, compression_level);
  png_write_info(png, info);
  if (bit_depth == 16 && hostIsLittleEndian()) png_set_swap(png);
  return true;
}

bool writeRow(png_structp png, png_const_bytep row) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_write_row(png, row);
  return true;
}

bool writeEnd(png_structp png, png_infop info) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_write_end(png, info);
  return true;
}

// ---- owners of the libpng structures ---------------------------------------------------------

class PngReadStruct {
 public:
  explicit PngReadStruct(PngIo* io) {
    png_ = png_create_read_struct(PNG_LIBPNG_VER_STRING, io, onPngError, onPngWarning);
    if (png_ != nullptr) info_ = png_create_info_struct(png_);
    if (png_ == nullptr || info_ == nullptr) {
      png_destroy_read_struct(&png_, &info_, nullptr);
      throw std::bad_alloc();
    }
    png_set_read_fn(png_, io, readFromMemory);
    png_set_user_limits(png_, kMaxImageDimension, kMaxImageDimension);
  }
  ~PngReadStruct() { png_destroy_read_struct(&png_, &info_, nullptr); }
  PngReadStruct(const PngReadStruct&) = delete;
  PngReadStruct& operator=(const PngReadStruct&) = delete;

  png_structp png() const { return png_; }
  png_infop info() const { return info_; }

 private:
  png_structp png_ = nullptr;
  png_infop info_ = nullptr;
};

class PngWriteStruct {
 public:
  explicit PngWriteStruct(PngIo* io) {
    png_ = png_create_write_struct(PNG_LIBPNG_VER_STRING, io, onPngError, onPngWarning);
    if (png_ != nullptr) info_ = png_create_info_struct(png_);
    if (png_ == nullptr || info_ == nullptr) {
      png_destroy_write_struct(&png_, &info_);
      throw std::bad_alloc();
    }
    png_set_write_fn(png_, io, writeToVector, flushNothing);
  }
  ~PngWriteStruct() { png_destroy_write_struct(&png_, &info_); }
  PngWriteStruct(const PngWriteStruct&) = delete;
  PngWriteStruct& operator=(const PngWriteStruct&) = delete;

  png_structp png() const { return png_; }
  png_infop info() const { return info_; }

 private:
  png_structp png_ = nullptr;
  png_infop info_ = nullptr;
};

int fileChannels(int color_type) {
  switch (color_type) {
    case PNG_COLOR_TYPE_GRAY:
      return 1;
    case PNG_COLOR_TYPE_GRAY_ALPHA:
      return 2;
    case PNG_COLOR_TYPE_RGB_ALPHA:
      return 4;
    default:  // RGB, palette
      return 3;
  }
}

/// Encodes an image whose elements are whole PNG pixels of `bit_depth` samples (16-bit samples
/// in native byte order; libpng swaps them on little-endian hosts).
template <typename T>
std::vector<unsigned char> encodeRows(ImageView<const T> image, int bit_depth, int color_type,
                                      const PngWriteOptions& options) {
  if (image.empty()) throw InputError("cannot encode an empty image as PNG");
  if (options.compression_level < 0 || options.compression_level > 9)
    throw InputError("PNG compression level " + std::to_string(options.compression_level) +
                     " is outside 0..9");
  std::vector<unsigned char> out;
  PngIo io;
  io.sink = &out;
  PngWriteStruct writer(&io);
  png_structp png = writer.png();
  bool ok = writeHeader(png, writer.info(), static_cast<png_uint_32>(image.width),
                        static_cast<png_uint_32>(image.height), bit_depth, color_type,
                        options.compression_level);
  for (int y = 0; ok && y < image.height; ++y)
    ok = writeRow(png, reinterpret_cast<png_const_bytep>(image.row(y)));
  ok = ok && writeEnd(png, writer.info());
  if (!ok) throw Error(std::string("cannot encode PNG: ") + io.message);
  return out;
}

}  // namespace

namespace detail {

template <typename T>
ImageFileInfo decodePng(const unsigned char* data, std::size_t size, const std::string& where,
                        Image<T>& out) {
  PngIo io;
  io.data = data;
  io.size = size;
  PngReadStruct reader(&io);
  png_structp png = reader.png();
  png_infop info = reader.info();
  const auto fail = [&] { throwDecodeError(where, std::string("PNG: ") + io.message); };

  if (!readInfo(png, info)) fail();
  ImageFileInfo file;
  file.format = ImageFileFormat::Png;
  file.width = static_cast<int>(png_get_image_width(png, info));
  file.height = static_cast<int>(png_get_image_height(png, info));
  file.channels = fileChannels(png_get_color_type(png, info));
  file.bit_depth = png_get_bit_depth(png, info);
  checkImageSize(where, file.width, file.height);

  int passes = 1;
  if (!setReadTransforms(png, info, &passes)) fail();
  const int channels = png_get_channels(png, info);
  const int depth = png_get_bit_depth(png, info);
  const std::size_t row_bytes = png_get_rowbytes(png, info);
  if ((channels != 1 && channels != 3) || (depth != 8 && depth != 16) ||
      row_bytes != static_cast<std::size_t>(file.width) * channels * (depth / 8))
    throwDecodeError(where, "PNG: unsupported pixel layout (" + std::to_string(channels) +
                                " channels of " + std::to_string(depth) + " bits)");

  out.resize(file.width, file.height);
  if (channels == 1 && depth == 8 * static_cast<int>(sizeof(T))) {
    // Same layout as the output: decode in place.
    for (int pass = 0; pass < passes; ++pass)
      for (int y = 0; y < file.height; ++y)
        if (!readRow(png, reinterpret_cast<png_bytep>(out.row(y)))) fail();
  } else if (passes == 1) {
    std::vector<unsigned char> row(row_bytes);
    for (int y = 0; y < file.height; ++y) {
      if (!readRow(png, row.data())) fail();
      rowToGrey(row.data(), depth, channels, file.width, out.row(y));
    }
  } else {
    // Interlaced: every pass revisits every row, so the whole image is decoded first.
    std::vector<unsigned char> all(row_bytes * static_cast<std::size_t>(file.height));
    for (int pass = 0; pass < passes; ++pass)
      for (int y = 0; y < file.height; ++y)
        if (!readRow(png, all.data() + row_bytes * static_cast<std::size_t>(y))) fail();
    for (int y = 0; y < file.height; ++y)
      rowToGrey(all.data() + row_bytes * static_cast<std::size_t>(y), depth, channels, file.width,
                out.row(y));
  }
  if (!readEnd(png)) fail();
  return file;
}

template ImageFileInfo decodePng(const unsigned char*, std::size_t, const std::string&, ImageU8&);
template ImageFileInfo decodePng(const unsigned char*, std::size_t, const std::string&, ImageU16&);

}  // namespace detail

std::vector<unsigned char> encodePng(ImageView<const std::uint8_t> image,
                                     const PngWriteOptions& options) {
  return encodeRows(image, 8, PNG_COLOR_TYPE_GRAY, options);
}

std::vector<unsigned char> encodePng(ImageView<const std::uint16_t> image,
                                     const PngWriteOptions& options) {
  return encodeRows(image, 16, PNG_COLOR_TYPE_GRAY, options);
}

std::vector<unsigned char> encodePng(ImageView<const Rgb8> image, const PngWriteOptions& options) {
  return encodeRows(image, 8, PNG_COLOR_TYPE_RGB, options);
}

}  // namespace ldsm::calib
