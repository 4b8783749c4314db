// Vocabulary files (docs/loop-closure.md): the engine's parser of the bytes, and the file reader
// that validates them.
#include "fuzz_input.h"
#include "ldsm/drivers/vocabulary_file.h"
#include "loop/vocabulary.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  ldsm::fuzz::parseOrReject([&] { ldsm::loop::Vocabulary::deserialize(data, size, "vocabulary"); });
  const std::string path = ldsm::fuzz::asFile(data, size, "vocabulary.bin");
  ldsm::fuzz::parseOrReject([&] { ldsm::drivers::readVocabularyFile(path); });
  return 0;
}
