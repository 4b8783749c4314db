#include "ldsm/drivers/vocabulary_file.h"

#include "ldsm/calib/image_file.h"
#include "ldsm/drivers/atomic_file.h"

namespace ldsm::drivers {

VocabularyFile readVocabularyFile(const std::string& path) {
  VocabularyFile file;
  calib::readFileBytes(path, file.bytes);
  file.summary = loop::inspectVocabulary(file.bytes.data(), file.bytes.size(), path);
  return file;
}

void writeVocabularyFile(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  loop::inspectVocabulary(bytes.data(), bytes.size(), path + " (data to write)");
  writeFileAtomically(path, std::string(bytes.begin(), bytes.end()));
}

}  // namespace ldsm::drivers
