// Point clouds as `ldsm view` reads them (points.ply): ASCII and binary little-endian PLY.
#include "fuzz_input.h"
#include "ldsm/drivers/ply_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = ldsm::fuzz::asFile(data, size, "points.ply");
  ldsm::fuzz::parseOrReject([&] { ldsm::drivers::readPly(path); });
  return 0;
}
