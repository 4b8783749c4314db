// The map file format (docs/map-file.md): a saved map (map_data.h) as versioned, checksummed,
// little-endian bytes and back. Core does no file I/O: ldsm/drivers/map_file_io.h reads and
// writes the files.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "mapfile/map_data.h"

namespace ldsm {

/// The bytes of a map file. Deterministic: the same map gives the same bytes, and so does
/// encoding what decodeMap() returned for them. Throws ldsm::Error "map to save: section ...:
/// ..." when the map fails a check decodeMap() makes (so that every file written loads).
std::vector<std::uint8_t> encodeMap(const MapData& map);

/// Reads a map file's bytes. Throws ldsm::InputError "<where>: <what is wrong>" naming the section
/// (and the keyframe, point or edge) for anything but a sound map of a version this build reads:
/// another file, a newer version, a truncated or corrupt file (a checksum per section), counts
/// beyond the data, non-finite values, ids that do not exist.
MapData decodeMap(const std::uint8_t* data, std::size_t size, const std::string& where);

}  // namespace ldsm
