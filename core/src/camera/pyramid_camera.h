// The ideal pinhole the engine works in, at every pyramid level. Level l halves the resolution
// l times; pixel centres stay at integer coordinates, so cx_l = (cx + 0.5) / 2^l - 0.5.
#pragma once

#include <Eigen/Core>
#include <array>

#include "ldsm/camera/calibration.h"

namespace ldsm {

constexpr int kMaxPyramidLevels = 8;

struct LevelCamera {
  float fx = 0, fy = 0, cx = 0, cy = 0;
  float fxi = 0, fyi = 0, cxi = 0, cyi = 0;  ///< inverse: x = fxi * u + cxi
  int width = 0, height = 0;

  Eigen::Vector2f project(const Eigen::Vector3f& p) const {
    return {fx * p.x() / p.z() + cx, fy * p.y() / p.z() + cy};
  }
  /// The ray through pixel (u, v) with z = 1.
  Eigen::Vector3f unproject(float u, float v) const { return {fxi * u + cxi, fyi * v + cyi, 1.f}; }
  Eigen::Matrix3f K() const {
    Eigen::Matrix3f k;
    k << fx, 0, cx, 0, fy, cy, 0, 0, 1;
    return k;
  }
};

class PyramidCamera {
 public:
  PyramidCamera() = default;
  PyramidCamera(const PinholeIntrinsics& k, int levels) : intrinsics_(k), levels_(levels) {
    for (int l = 0; l < levels; ++l) {
      const float s = 1.f / static_cast<float>(1 << l);
      LevelCamera& c = cams_[l];
      c.fx = static_cast<float>(k.fx) * s;
      c.fy = static_cast<float>(k.fy) * s;
      c.cx = (static_cast<float>(k.cx) + 0.5f) * s - 0.5f;
      c.cy = (static_cast<float>(k.cy) + 0.5f) * s - 0.5f;
      c.fxi = 1.f / c.fx;
      c.fyi = 1.f / c.fy;
      c.cxi = -c.cx / c.fx;
      c.cyi = -c.cy / c.fy;
      c.width = k.width >> l;
      c.height = k.height >> l;
    }
  }
  int levels() const { return levels_; }
  const LevelCamera& operator[](int level) const { return cams_[level]; }
  /// The full-resolution pinhole the levels were made from.
  const PinholeIntrinsics& intrinsics() const { return intrinsics_; }

 private:
  PinholeIntrinsics intrinsics_{};
  std::array<LevelCamera, kMaxPyramidLevels> cams_{};
  int levels_ = 0;
};

}  // namespace ldsm
