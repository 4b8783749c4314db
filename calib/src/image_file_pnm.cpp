// Binary PGM (P5) and PPM (P6) decoding: a text header "P5 <width> <height> <maxval>" with
// '#' comments, one whitespace byte, then big-endian samples (two bytes each when maxval > 255).
#include <cstdint>
#include <string>

#include "image_file_codecs.h"

namespace ldsm::calib::detail {
namespace {

bool isSpace(unsigned char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

/// Reader of the header fields.
class PnmHeader {
 public:
  PnmHeader(const unsigned char* data, std::size_t size, const std::string& where)
      : data_(data), size_(size), where_(where) {}

  /// The next decimal field, after whitespace and comments.
  long long number(const char* field) {
    while (pos_ < size_) {
      if (isSpace(data_[pos_])) {
        ++pos_;
      } else if (data_[pos_] == '#') {
        while (pos_ < size_ && data_[pos_] != '\n' && data_[pos_] != '\r') ++pos_;
      } else {
        break;
      }
    }
    if (pos_ >= size_)
      throwDecodeError(where_, std::string("PNM: header ends before the ") + field);
    long long value = 0;
    const std::size_t start = pos_;
    while (pos_ < size_ && data_[pos_] >= '0' && data_[pos_] <= '9') {
      if (value > 1000000000LL)
        throwDecodeError(where_, std::string("PNM: ") + field + " too large");
      value = value * 10 + (data_[pos_] - '0');
      ++pos_;
    }
    if (pos_ == start) throwDecodeError(where_, std::string("PNM: ") + field + " is not a number");
    return value;
  }

  /// Skips the single whitespace byte that ends the header; returns the data offset.
  std::size_t endOfHeader() {
    if (pos_ >= size_ || !isSpace(data_[pos_]))
      throwDecodeError(where_, "PNM: no whitespace after the header");
    return pos_ + 1;
  }

 private:
  const unsigned char* data_;
  std::size_t size_;
  const std::string& where_;
  std::size_t pos_ = 2;  // after the magic number
};

int bitsFor(long long maxval) {
  int bits = 0;
  while ((1LL << bits) <= maxval) ++bits;
  return bits;
}

}  // namespace

template <typename T>
ImageFileInfo decodePnm(const unsigned char* data, std::size_t size, const std::string& where,
                        Image<T>& out) {
  const char kind = static_cast<char>(data[1]);
  if (kind != '5' && kind != '6')
    throwDecodeError(where, std::string("PNM: P") + kind +
                                (kind == '1' || kind == '4' ? " (bitmap)" : " (ASCII)") +
                                " is not supported (binary P5 and P6 are)");
  PnmHeader header(data, size, where);
  const long long width = header.number("width");
  const long long height = header.number("height");
  const long long maxval = header.number("maxval");
  checkImageSize(where, width, height);
  if (maxval < 1 || maxval > 65535)
    throwDecodeError(where, "PNM: maxval " + std::to_string(maxval) + " is outside 1..65535");
  const std::size_t offset = header.endOfHeader();

  ImageFileInfo file;
  file.format = ImageFileFormat::Pnm;
  file.width = static_cast<int>(width);
  file.height = static_cast<int>(height);
  file.channels = kind == '5' ? 1 : 3;
  file.bit_depth = bitsFor(maxval);
  const std::size_t sample_bytes = maxval > 255 ? 2 : 1;
  const std::size_t needed = static_cast<std::size_t>(width) * static_cast<std::size_t>(height) *
                             static_cast<std::size_t>(file.channels) * sample_bytes;
  if (size - offset < needed)
    throwDecodeError(where, "PNM: truncated data (" + std::to_string(size - offset) + " of " +
                                std::to_string(needed) + " bytes)");

  // Samples are scaled to the full range of 8 bits when maxval < 256, else of 16 bits (then
  // reduced to 8 bits like 16-bit PNG samples when T is 8-bit).
  const std::uint64_t max = static_cast<std::uint64_t>(maxval);
  const std::uint64_t full = maxval < 256 ? 255 : 65535;
  const unsigned char* p = data + offset;
  out.resize(file.width, file.height);
  for (int y = 0; y < file.height; ++y) {
    T* dst = out.row(y);
    for (int x = 0; x < file.width; ++x) {
      std::uint32_t s[3] = {0, 0, 0};
      for (int c = 0; c < file.channels; ++c) {
        s[c] = sample_bytes == 1 ? p[0] : static_cast<std::uint32_t>(p[0] << 8 | p[1]);
        p += sample_bytes;
        if (s[c] > max)
          throwDecodeError(where, "PNM: sample " + std::to_string(s[c]) + " at pixel (" +
                                      std::to_string(x) + ", " + std::to_string(y) +
                                      ") exceeds maxval " + std::to_string(maxval));
      }
      const std::uint64_t v = file.channels == 1 ? s[0] : lumaOf(s[0], s[1], s[2]);
      const auto scaled = static_cast<std::uint32_t>(max == full ? v : (v * full + max / 2) / max);
      if constexpr (sizeof(T) == 1) {
        dst[x] = full == 255 ? static_cast<T>(scaled) : scale16To8(scaled);
      } else {
        dst[x] = static_cast<T>(full == 255 ? scaled * 257u : scaled);
      }
    }
  }
  return file;
}

template ImageFileInfo decodePnm(const unsigned char*, std::size_t, const std::string&, ImageU8&);
template ImageFileInfo decodePnm(const unsigned char*, std::size_t, const std::string&, ImageU16&);

}  // namespace ldsm::calib::detail
