#include "ldsm/drivers/map_file_io.h"

#include "ldsm/calib/image_file.h"
#include "ldsm/drivers/atomic_file.h"

namespace ldsm::drivers {

std::vector<std::uint8_t> readMapFile(const std::string& path) {
  std::vector<std::uint8_t> bytes;
  calib::readFileBytes(path, bytes);
  return bytes;
}

void writeMapFile(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  writeFileAtomically(path, bytes.data(), bytes.size());
}

}  // namespace ldsm::drivers
