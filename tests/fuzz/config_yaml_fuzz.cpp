// The configuration YAML (`ldsm run --config`), parsed and validated.
#include "fuzz_input.h"
#include "ldsm/drivers/config_yaml.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  ldsm::fuzz::parseOrReject(
      [&] { ldsm::drivers::parseConfigYaml(ldsm::fuzz::asText(data, size), "config.yaml"); });
  return 0;
}
