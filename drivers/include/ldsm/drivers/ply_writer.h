// Point clouds as PLY files (readable by MeshLab, CloudCompare, Open3D).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace ldsm::drivers {

enum class PlyEncoding { BinaryLittleEndian, Ascii };

/// Writes points (float x, y, z) with optional per-point colours (uchar red, green, blue) and/or
/// intensities (float intensity); pass empty vectors to leave them out. The file is replaced
/// atomically. Throws ldsm::InputError when a non-empty colour or intensity list differs in size
/// from the points or a coordinate/intensity is not finite, ldsm::Error when writing fails.
void writePly(const std::string& path, const std::vector<Eigen::Vector3f>& points,
              const std::vector<std::array<std::uint8_t, 3>>& colours = {},
              const std::vector<float>& intensities = {},
              PlyEncoding encoding = PlyEncoding::BinaryLittleEndian);

}  // namespace ldsm::drivers
