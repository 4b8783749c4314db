// camera.txt (DSO's calibration format, every model it names).
#include "fuzz_input.h"
#include "ldsm/calib/dso_camera_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  ldsm::fuzz::parseOrReject(
      [&] { ldsm::calib::parseDsoCameraFile(ldsm::fuzz::asText(data, size), "camera.txt"); });
  return 0;
}
