#include "ldsm/calib/photometric_files.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "ldsm/calib/image_file.h"
#include "ldsm/camera/photometric_model.h"
#include "ldsm/error.h"
#include "text_file.h"

namespace ldsm::calib {

std::array<float, 256> readInverseResponse(const std::string& path) {
  const auto lines = detail::contentLines(detail::readTextFile(path));
  std::array<float, 256> g{};
  std::size_t count = 0;
  int last_line = 1;
  for (const auto& line : lines) {
    last_line = line.number;
    for (const auto& token : line.tokens) {
      if (count == g.size())
        throw InputError(atLine(path, line.number,
                                "more than 256 values (pcalib.txt holds G^-1 "
                                "for the pixel values 0..255)"));
      const double v = detail::parseNumber(token, path, line.number,
                                           "inverse response value " + std::to_string(count));
      g[count] = static_cast<float>(v);
      if (count > 0 && g[count] < g[count - 1])
        throw InputError(atLine(path, line.number,
                                "inverse response decreases at index " + std::to_string(count) +
                                    " (" + token + " < " + detail::formatNumber(g[count - 1]) +
                                    "); it must be non-decreasing"));
      ++count;
    }
  }
  if (count != g.size())
    throw InputError(atLine(
        path, last_line, "expected 256 inverse response values, found " + std::to_string(count)));
  if (!(g[255] > g[0])) throw InputError(atLine(path, last_line, "inverse response is constant"));
  return g;
}

void writeInverseResponse(const std::string& path, const std::array<float, 256>& g) {
  std::string text;
  for (std::size_t i = 0; i < g.size(); ++i) {
    if (!std::isfinite(g[i]))
      throw InputError(path + ": not written: inverse response value " + std::to_string(i) +
                       " is not finite");
    text += (i > 0 ? " " : "") + detail::formatNumber(g[i]);
  }
  detail::writeTextFile(path, text + "\n");
}

ImageF readVignette(const std::string& path) {
  if (!std::filesystem::is_regular_file(path))
    throw InputError(path + ": cannot open vignette image (no such file)");
  ImageU16 raw;
  const ImageFileInfo file = readImage(path, raw);
  if (file.channels != 1)
    throw InputError(path + ": vignette must be a single-channel image (has " +
                     std::to_string(file.channels) + " channels)");
  std::uint16_t max_value = 0;
  for (int y = 0; y < raw.height(); ++y)
    for (int x = 0; x < raw.width(); ++x) max_value = std::max(max_value, raw(x, y));
  if (max_value == 0) throw InputError(path + ": vignette is all zero");
  ImageF out(raw.width(), raw.height());
  for (int y = 0; y < raw.height(); ++y) {
    for (int x = 0; x < raw.width(); ++x) {
      if (raw(x, y) == 0)
        throw InputError(path + ": vignette is zero at pixel (" + std::to_string(x) + ", " +
                         std::to_string(y) + "); it must be positive everywhere");
      out(x, y) = static_cast<float>(static_cast<double>(raw(x, y)) / max_value);
    }
  }
  return out;
}

void writeVignette(const std::string& path, const ImageF& vignette) {
  if (vignette.empty()) throw InputError(path + ": not written: the vignette is empty");
  float max_value = 0.0f;
  for (int y = 0; y < vignette.height(); ++y)
    for (int x = 0; x < vignette.width(); ++x) {
      const float v = vignette(x, y);
      if (!(std::isfinite(v) && v > 0.0f))
        throw InputError(path + ": not written: vignette value at (" + std::to_string(x) + ", " +
                         std::to_string(y) + ") is not finite and positive");
      max_value = std::max(max_value, v);
    }
  ImageU16 img(vignette.width(), vignette.height());
  for (int y = 0; y < vignette.height(); ++y)
    for (int x = 0; x < vignette.width(); ++x)
      img(x, y) = static_cast<std::uint16_t>(
          std::max(1L, std::lround(65535.0 * vignette(x, y) / max_value)));
  writePng(path, img.view());
}

PhotometricCalibration loadPhotometricCalibration(const std::string& pcalib_path,
                                                  const std::string& vignette_path, int width,
                                                  int height) {
  PhotometricCalibration calib;
  if (!pcalib_path.empty()) {
    calib.inverse_response = readInverseResponse(pcalib_path);
    calib.has_response = true;
  }
  if (!vignette_path.empty()) {
    calib.vignette = readVignette(vignette_path);
    if (width > 0 && height > 0 &&
        (calib.vignette.width() != width || calib.vignette.height() != height))
      throw InputError(vignette_path + ": vignette is " + std::to_string(calib.vignette.width()) +
                       "x" + std::to_string(calib.vignette.height()) + " but the images are " +
                       std::to_string(width) + "x" + std::to_string(height));
  }
  validatePhotometricCalibration(calib, calib.vignette.width(), calib.vignette.height());
  return calib;
}

}  // namespace ldsm::calib
