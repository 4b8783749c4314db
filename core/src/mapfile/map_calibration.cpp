#include "mapfile/map_calibration.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace ldsm {
namespace {

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.9g", v);
  return buf;
}

std::string hex(std::uint64_t v) {
  char buf[24];
  std::snprintf(buf, sizeof(buf), "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

bool close(double a, double b) {
  constexpr double kRelative = 1e-5;
  return std::abs(a - b) <= kRelative * std::max({1.0, std::abs(a), std::abs(b)});
}

std::string photometricText(const MapCalibration& c) {
  std::string s = c.has_response ? (c.has_vignette ? "response and vignette" : "response only")
                                 : (c.has_vignette ? "vignette only" : "none");
  return s + ", hash " + hex(c.photometric_hash);
}

class Fnv1a {
 public:
  void byte(std::uint8_t b) {
    h_ ^= b;
    h_ *= 0x100000001B3ull;
  }
  void u32(std::uint32_t v) {
    for (int i = 0; i < 4; ++i) byte(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void f32(float f) {
    std::uint32_t bits = 0;
    std::memcpy(&bits, &f, 4);
    u32(bits);
  }
  std::uint64_t value() const { return h_; }

 private:
  std::uint64_t h_ = 0xCBF29CE484222325ull;
};

}  // namespace

std::string mapCalibrationMismatch(const MapCalibration& saved, const MapCalibration& now) {
  const PinholeIntrinsics& a = saved.camera;
  const PinholeIntrinsics& b = now.camera;
  if (a.width != b.width || a.height != b.height)
    return "image size " + std::to_string(a.width) + "x" + std::to_string(a.height) +
           " in the map, " + std::to_string(b.width) + "x" + std::to_string(b.height) + " now";
  const std::pair<const char*, std::pair<double, double>> values[] = {
      {"fx", {a.fx, b.fx}}, {"fy", {a.fy, b.fy}}, {"cx", {a.cx, b.cx}}, {"cy", {a.cy, b.cy}}};
  for (const auto& [name, v] : values)
    if (!close(v.first, v.second))
      return std::string(name) + " " + number(v.first) + " in the map, " + number(v.second) +
             " now";
  if (saved.has_response != now.has_response || saved.has_vignette != now.has_vignette ||
      saved.photometric_hash != now.photometric_hash)
    return "photometric calibration " + photometricText(saved) + " in the map, " +
           photometricText(now) + " now";
  return "";
}

std::uint64_t photometricHash(const PhotometricCalibration& photometric) {
  const bool vignette = !photometric.vignette.empty();
  if (!photometric.has_response && !vignette) return 0;
  Fnv1a h;
  if (photometric.has_response) {
    h.byte('R');
    for (float v : photometric.inverse_response) h.f32(v);
  }
  if (vignette) {
    const ImageF& v = photometric.vignette;
    h.byte('V');
    h.u32(static_cast<std::uint32_t>(v.width()));
    h.u32(static_cast<std::uint32_t>(v.height()));
    for (int y = 0; y < v.height(); ++y)
      for (int x = 0; x < v.width(); ++x) h.f32(v(x, y));
  }
  return h.value();
}

MapCalibration makeMapCalibration(const PinholeIntrinsics& camera, double radial_k,
                                  const PhotometricCalibration& photometric) {
  MapCalibration c;
  c.camera = camera;
  c.radial_k = radial_k;
  c.has_response = photometric.has_response;
  c.has_vignette = !photometric.vignette.empty();
  c.photometric_hash = photometricHash(photometric);
  return c;
}

}  // namespace ldsm
