// KITTI calib.txt (P0..P3 projection matrices).
#include "fuzz_input.h"
#include "ldsm/calib/kitti_calib.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  ldsm::fuzz::parseOrReject([&] {
    ldsm::calib::parseKittiCalib(ldsm::fuzz::asText(data, size), "calib.txt", 0, 1241, 376);
  });
  return 0;
}
