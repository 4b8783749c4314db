// The vignette image (8- or 16-bit PNG, or any format the image decoders read).
#include "fuzz_input.h"
#include "ldsm/calib/photometric_files.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = ldsm::fuzz::asFile(data, size, "vignette.png");
  ldsm::fuzz::parseOrReject([&] { ldsm::calib::readVignette(path); });
  return 0;
}
