// Shared by the fuzz targets (docs/reliability.md, "Fuzzing"): a parser of outside input may
// reject its input only with an ldsm::Error naming what is wrong; anything else (a crash, a
// sanitizer report, another exception, a hang) is a bug. The same targets build as libFuzzer
// fuzzers (scripts/fuzz.sh, clang) and, in the test suite, as replays of their corpora.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "ldsm/error.h"

namespace ldsm::fuzz {

inline std::string asText(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

/// The input as a file, for the parsers that read from a path: one file per process and name,
/// in /dev/shm when it exists (no disk traffic at a million executions).
inline std::string asFile(const std::uint8_t* data, std::size_t size, const char* name) {
  static const std::string dir = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
  const std::string path =
      dir + "/ldsm_fuzz_" + std::to_string(static_cast<long>(getpid())) + "_" + name;
  if (FILE* f = std::fopen(path.c_str(), "wb")) {
    if (size > 0) std::fwrite(data, 1, size, f);
    std::fclose(f);
  }
  return path;
}

/// Runs `parse`; an ldsm::Error is the parser's proper answer to bad input (printed when
/// LDSM_FUZZ_VERBOSE is set, to see which seeds a parser accepts).
template <typename Parse>
void parseOrReject(Parse&& parse) {
  static const bool verbose = std::getenv("LDSM_FUZZ_VERBOSE") != nullptr;
  try {
    parse();
    if (verbose) std::fprintf(stderr, "  accepted\n");
  } catch (const Error& e) {
    if (verbose) std::fprintf(stderr, "  rejected: %s\n", e.what());
  }
}

}  // namespace ldsm::fuzz
