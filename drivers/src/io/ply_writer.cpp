#include "ldsm/drivers/ply_writer.h"

#include <charconv>
#include <cmath>
#include <cstring>

#include "ldsm/drivers/atomic_file.h"
#include "ldsm/error.h"

namespace ldsm::drivers {

namespace {

void appendFloatLE(std::string& out, float v) {
  std::uint32_t bits = 0;
  std::memcpy(&bits, &v, sizeof(bits));
  for (int i = 0; i < 4; ++i) out += static_cast<char>((bits >> (8 * i)) & 0xffu);
}

// Shortest text that reads back to the same float.
void appendNumber(std::string& out, float v) {
  char buf[32];
  const auto res = std::to_chars(buf, buf + sizeof(buf), v);
  out.append(buf, res.ptr);
}

void checkInput(const std::string& path, const std::vector<Eigen::Vector3f>& points,
                const std::vector<std::array<std::uint8_t, 3>>& colours,
                const std::vector<float>& intensities) {
  if (!colours.empty() && colours.size() != points.size()) {
    throw InputError(path + ": " + std::to_string(points.size()) + " points but " +
                     std::to_string(colours.size()) + " colours");
  }
  if (!intensities.empty() && intensities.size() != points.size()) {
    throw InputError(path + ": " + std::to_string(points.size()) + " points but " +
                     std::to_string(intensities.size()) + " intensities");
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite() || (!intensities.empty() && !std::isfinite(intensities[i]))) {
      throw InputError(path + ": point " + std::to_string(i) + " is not finite");
    }
  }
}

}  // namespace

void writePly(const std::string& path, const std::vector<Eigen::Vector3f>& points,
              const std::vector<std::array<std::uint8_t, 3>>& colours,
              const std::vector<float>& intensities, PlyEncoding encoding) {
  checkInput(path, points, colours, intensities);
  const bool binary = encoding == PlyEncoding::BinaryLittleEndian;
  std::string out = "ply\n";
  out += binary ? "format binary_little_endian 1.0\n" : "format ascii 1.0\n";
  out += "comment written by ldsm\n";
  out += "element vertex " + std::to_string(points.size()) + "\n";
  out += "property float x\nproperty float y\nproperty float z\n";
  if (!colours.empty()) out += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  if (!intensities.empty()) out += "property float intensity\n";
  out += "end_header\n";

  for (std::size_t i = 0; i < points.size(); ++i) {
    if (binary) {
      for (int k = 0; k < 3; ++k) appendFloatLE(out, points[i](k));
      if (!colours.empty()) {
        for (const std::uint8_t c : colours[i]) out += static_cast<char>(c);
      }
      if (!intensities.empty()) appendFloatLE(out, intensities[i]);
    } else {
      for (int k = 0; k < 3; ++k) {
        if (k > 0) out += ' ';
        appendNumber(out, points[i](k));
      }
      if (!colours.empty()) {
        for (const std::uint8_t c : colours[i]) out += ' ' + std::to_string(c);
      }
      if (!intensities.empty()) {
        out += ' ';
        appendNumber(out, intensities[i]);
      }
      out += '\n';
    }
  }
  writeFileAtomically(path, out);
}

}  // namespace ldsm::drivers
