// Reads little-endian values from one section of a map file, checking every read against the
// bytes left: the reading half of the map file codec (docs/map-file.md). Every failure is an
// ldsm::InputError "<file>: section <TAG> (<name>)[: <context>]: <what is wrong>".
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <utility>

#include "mapfile/byte_order.h"

namespace ldsm::mapfile {

class ByteReader {
 public:
  /// `label` starts every error message: the file and the section.
  ByteReader(const std::uint8_t* data, std::size_t size, std::string label)
      : p_(data), end_(data + size), label_(std::move(label)) {}

  std::uint8_t u8() { return *take(1); }
  std::uint32_t u32() { return loadU32(take(4)); }
  std::uint64_t u64() { return loadU64(take(8)); }
  std::int32_t i32() { return static_cast<std::int32_t>(u32()); }
  std::int64_t i64() { return static_cast<std::int64_t>(u64()); }
  float f32() {
    const std::uint32_t bits = u32();
    float v = 0.f;
    std::memcpy(&v, &bits, 4);
    return v;
  }
  double f64() {
    const std::uint64_t bits = u64();
    double v = 0.0;
    std::memcpy(&v, &bits, 8);
    return v;
  }
  /// The next `size` bytes (checked), for copying.
  const std::uint8_t* bytes(std::size_t size) { return take(size); }

  /// A u32 count of records that take at least `min_bytes` each, checked against the bytes left
  /// before anything is allocated for them (a corrupt count cannot ask for gigabytes).
  std::size_t count(const char* what, std::size_t min_bytes);

  std::size_t remaining() const { return static_cast<std::size_t>(end_ - p_); }
  /// Fails unless every byte of the section was read.
  void expectEnd();

  /// Names what is being read in later messages ("keyframe 12"); empty: the section itself.
  void setContext(std::string context) { context_ = std::move(context); }
  /// Throws InputError "<label>[: <context>]: <what>".
  [[noreturn]] void fail(const std::string& what) const;

 private:
  const std::uint8_t* take(std::size_t n) {
    if (remaining() < n) truncated(n);
    const std::uint8_t* p = p_;
    p_ += n;
    return p;
  }
  [[noreturn]] void truncated(std::size_t n) const;

  const std::uint8_t* p_;
  const std::uint8_t* end_;
  std::string label_;
  std::string context_;
};

}  // namespace ldsm::mapfile
