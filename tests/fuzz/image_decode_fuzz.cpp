// The PNG, JPEG and PGM/PPM decoders (chosen by the data's signature), to 8 and 16 bits.
#include "fuzz_input.h"
#include "ldsm/calib/image_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  ldsm::ImageU8 u8;
  ldsm::ImageU16 u16;
  ldsm::fuzz::parseOrReject([&] { ldsm::calib::decodeImage(data, size, "image", u8); });
  ldsm::fuzz::parseOrReject([&] { ldsm::calib::decodeImage(data, size, "image", u16); });
  return 0;
}
