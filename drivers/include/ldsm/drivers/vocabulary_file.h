// Vocabulary files for loop detection (the binary format of docs/loop-closure.md, "Vocabulary"):
// reading with full validation, writing atomically.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "ldsm/loop/vocabulary_builder.h"

namespace ldsm::drivers {

/// A vocabulary file's bytes (what the engine loads) and what they hold.
struct VocabularyFile {
  std::vector<std::uint8_t> bytes;
  loop::VocabularySummary summary;
};

/// Reads and validates a vocabulary file. Throws ldsm::InputError "<path>: ..." when the file is
/// missing or unreadable, not a vocabulary, of an unsupported version, truncated or corrupt.
VocabularyFile readVocabularyFile(const std::string& path);

/// Writes serialised vocabulary bytes to `path` atomically (a crash never leaves half a file).
/// Throws ldsm::InputError when `bytes` is not a valid vocabulary (nothing is written then) and
/// ldsm::Error naming the path when writing fails.
void writeVocabularyFile(const std::string& path, const std::vector<std::uint8_t>& bytes);

}  // namespace ldsm::drivers
