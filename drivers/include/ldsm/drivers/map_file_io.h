// Map files (docs/map-file.md) on disk: reading the bytes, writing them atomically. Decoding and
// checking them is core's (ldsm/map_file.h, and the System when it loads a map).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace ldsm::drivers {

/// The bytes of the map file `path`. Throws ldsm::InputError "<path>: ..." when it is missing or
/// unreadable (nothing is checked here: the decoder names what is wrong with the contents).
std::vector<std::uint8_t> readMapFile(const std::string& path);

/// Writes a map file's bytes to `path` atomically: a temporary file beside it, flushed, then
/// renamed over `path`, so that a crash or a full disk never leaves half a map. Throws ldsm::Error
/// naming the path when writing fails (nothing is left behind then).
void writeMapFile(const std::string& path, const std::vector<std::uint8_t>& bytes);

}  // namespace ldsm::drivers
