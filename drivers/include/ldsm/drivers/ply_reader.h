// Reading point clouds from PLY files: the vertex positions and, when present, their colours and
// intensities (what ply_writer.h writes, and the common variants other tools write).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace ldsm::drivers {

struct PlyPoints {
  std::vector<Eigen::Vector3f> points;
  std::vector<std::array<std::uint8_t, 3>> colours;  ///< empty when the file has none
  std::vector<float> intensities;                    ///< empty when the file has none
};

/// Reads the "vertex" element (x, y, z and optionally red, green, blue and intensity; other
/// properties are skipped) of an ASCII or binary little-endian PLY file. Throws ldsm::InputError
/// "path: what" for a missing file, a malformed header, an unsupported format or property type,
/// a vertex element without x, y, z, or a file shorter than its header says.
PlyPoints readPly(const std::string& path);

}  // namespace ldsm::drivers
