// Kalibr camchain YAML and EuRoC sensor.yaml.
#include "fuzz_input.h"
#include "ldsm/calib/kalibr_yaml.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  ldsm::fuzz::parseOrReject([&] {
    ldsm::calib::parseKalibrCameraYaml(ldsm::fuzz::asText(data, size), "camchain.yaml", "cam0");
  });
  return 0;
}
