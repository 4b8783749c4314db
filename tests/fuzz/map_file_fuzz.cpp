// Map files (docs/map-file.md): the decoder of the bytes. Each input is decoded as it is, then
// again with its checksums made to match (as a forger would), so that mutations reach the section
// parsers and the consistency checks behind the CRC-32s. A map the decoder accepts must encode
// again deterministically: encoding what it decoded, decoding and encoding that gives the same
// bytes.
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "fuzz_input.h"
#include "mapfile/byte_order.h"
#include "mapfile/crc32.h"
#include "mapfile/map_codec.h"
#include "mapfile/map_format.h"

namespace {

namespace mf = ldsm::mapfile;

void decodeAndEncodeAgain(const std::uint8_t* data, std::size_t size) {
  ldsm::fuzz::parseOrReject([&] {
    const ldsm::MapData map = ldsm::decodeMap(data, size, "map");
    try {
      const std::vector<std::uint8_t> again = ldsm::encodeMap(map);
      const std::vector<std::uint8_t> third =
          ldsm::encodeMap(ldsm::decodeMap(again.data(), again.size(), "map (encoded again)"));
      if (third != again) {
        std::fprintf(stderr, "map_file: encoding a decoded map is not deterministic\n");
        std::abort();
      }
    } catch (const ldsm::Error& e) {
      std::fprintf(stderr, "map_file: a decoded map does not encode again: %s\n", e.what());
      std::abort();
    }
  });
}

/// The input with every checksum recomputed where the table lets it be; false when the header
/// or the table does not fit.
bool withMatchingChecksums(const std::uint8_t* data, std::size_t size,
                           std::vector<std::uint8_t>& out) {
  if (size < mf::kHeaderBytes) return false;
  const std::uint64_t count = mf::loadU32(data + 12);
  if (count > mf::kMaxSections || size < mf::kHeaderBytes + count * mf::kTableEntryBytes)
    return false;
  out.assign(data, data + size);
  std::uint8_t* table = out.data() + mf::kHeaderBytes;
  for (std::uint64_t i = 0; i < count; ++i) {
    std::uint8_t* e = table + i * mf::kTableEntryBytes;
    const std::uint64_t offset = mf::loadU64(e + 8);
    const std::uint64_t length = mf::loadU64(e + 16);
    if (offset <= size && length <= size - offset)
      mf::storeU32(e + 4, mf::crc32(out.data() + offset, static_cast<std::size_t>(length)));
  }
  mf::storeU32(out.data() + 16,
               mf::crc32(table, static_cast<std::size_t>(count) * mf::kTableEntryBytes,
                         mf::crc32(out.data(), 16)));
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  decodeAndEncodeAgain(data, size);
  std::vector<std::uint8_t> forged;
  if (withMatchingChecksums(data, size, forged)) decodeAndEncodeAgain(forged.data(), forged.size());
  return 0;
}
