// Appends little-endian values to a byte buffer, whatever the host's byte order: the writing half
// of the map file codec (docs/map-file.md).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "ldsm/error.h"
#include "mapfile/byte_order.h"

namespace ldsm::mapfile {

class ByteWriter {
 public:
  explicit ByteWriter(std::vector<std::uint8_t>& out) : out_(out) {}

  void u8(std::uint8_t v) { out_.push_back(v); }
  void u32(std::uint32_t v) { put(v, 4); }
  void u64(std::uint64_t v) { put(v, 8); }
  void i32(std::int32_t v) { u32(static_cast<std::uint32_t>(v)); }
  void i64(std::int64_t v) { u64(static_cast<std::uint64_t>(v)); }
  /// IEEE-754 bits as they are (NaN payloads included).
  void f32(float v) {
    std::uint32_t bits = 0;
    std::memcpy(&bits, &v, 4);
    u32(bits);
  }
  void f64(double v) {
    std::uint64_t bits = 0;
    std::memcpy(&bits, &v, 8);
    u64(bits);
  }
  /// A record count as u32; more than a u32 holds is an ldsm::Error (no map is that big).
  void count(std::size_t n) {
    if (n > 0xFFFFFFFFu) throw Error("map to save: more than 2^32 - 1 records in one list");
    u32(static_cast<std::uint32_t>(n));
  }
  void bytes(const std::uint8_t* data, std::size_t size) {
    if (size > 0) out_.insert(out_.end(), data, data + size);
  }

  std::size_t size() const { return out_.size(); }

 private:
  void put(std::uint64_t v, int n) {
    std::uint8_t b[8];
    storeU64(b, v);
    out_.insert(out_.end(), b, b + n);
  }

  std::vector<std::uint8_t>& out_;
};

}  // namespace ldsm::mapfile
