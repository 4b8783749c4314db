// CRC-32 (the IEEE 802.3 / zlib / PNG polynomial, reflected, initial and final XOR 0xFFFFFFFF):
// the per-section checksum of the map file format (docs/map-file.md).
#pragma once

#include <cstddef>
#include <cstdint>

namespace ldsm::mapfile {

/// CRC-32 of `size` bytes; crc32(p, n) equals zlib's crc32(0, p, n). `previous` continues a
/// checksum over several pieces: crc32(b, m, crc32(a, n)) is the CRC of a followed by b.
std::uint32_t crc32(const std::uint8_t* data, std::size_t size, std::uint32_t previous = 0);

}  // namespace ldsm::mapfile
