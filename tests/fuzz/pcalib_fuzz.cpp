// pcalib.txt (the inverse response: 256 numbers).
#include "fuzz_input.h"
#include "ldsm/calib/photometric_files.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = ldsm::fuzz::asFile(data, size, "pcalib.txt");
  ldsm::fuzz::parseOrReject([&] { ldsm::calib::readInverseResponse(path); });
  return 0;
}
