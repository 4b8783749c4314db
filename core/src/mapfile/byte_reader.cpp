#include "mapfile/byte_reader.h"

#include "ldsm/error.h"

namespace ldsm::mapfile {

std::size_t ByteReader::count(const char* what, std::size_t min_bytes) {
  const std::uint64_t n = u32();
  if (min_bytes > 0 && n > remaining() / min_bytes) {
    fail(std::to_string(n) + " " + what + " need at least " + std::to_string(n * min_bytes) +
         " bytes, the section has " + std::to_string(remaining()) + " left (corrupt count)");
  }
  return static_cast<std::size_t>(n);
}

void ByteReader::expectEnd() {
  if (p_ != end_) fail(std::to_string(remaining()) + " unexpected bytes at the end of the section");
}

void ByteReader::fail(const std::string& what) const {
  throw InputError(label_ + (context_.empty() ? "" : ": " + context_) + ": " + what);
}

void ByteReader::truncated(std::size_t n) const {
  fail("data ends early (" + std::to_string(n) + " more bytes needed, " +
       std::to_string(remaining()) + " left)");
}

}  // namespace ldsm::mapfile
