// Map files (docs/map-file.md): the decoder of the bytes. A map it accepts must encode again
// deterministically: encoding what it decoded, decoding and encoding that gives the same bytes.
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "fuzz_input.h"
#include "mapfile/map_codec.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  ldsm::fuzz::parseOrReject([&] {
    const ldsm::MapData map = ldsm::decodeMap(data, size, "map");
    std::vector<std::uint8_t> again;
    try {
      again = ldsm::encodeMap(map);
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
  return 0;
}
