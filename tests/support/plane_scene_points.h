// Helpers for tests of direct alignment on a rendered PlaneScene: a pose from its tangent
// coordinates, the Isometry the renderer takes, and the stored points (PatchPoint) of a rendered
// host image on a grid of pixels with enough gradient.
#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "ldsm/image.h"
#include "math/se3.h"
#include "model/patch_point.h"

namespace ldsm::test {

/// exp of the tangent (translation tx, ty, tz; rotation rx, ry, rz).
inline SE3d tangentPose(double rx, double ry, double rz, double tx, double ty, double tz) {
  SE3d::Tangent x;
  x << tx, ty, tz, rx, ry, rz;
  return SE3d::exp(x);
}

inline Eigen::Isometry3d isometry(const SE3d& T_w_c) {
  Eigen::Isometry3d iso = Eigen::Isometry3d::Identity();
  iso.linear() = T_w_c.so3().matrix();
  iso.translation() = T_w_c.translation();
  return iso;
}

/// Points of `host` (with its inverse depths) every `step` pixels, `border` pixels in, where a
/// plane was hit and the central gradient is at least 4 grey levels.
inline std::vector<PatchPoint> gridPatchPoints(const ImageF& host, const ImageF& idepth, int step,
                                               int border) {
  std::vector<PatchPoint> points;
  for (int y = border; y < host.height() - border; y += step)
    for (int x = border; x < host.width() - border; x += step) {
      PatchPoint p;
      p.u = static_cast<float>(x);
      p.v = static_cast<float>(y);
      p.idepth = idepth(x, y);
      if (!(p.idepth > 0.f)) continue;
      const float gx = host(x + 1, y) - host(x - 1, y), gy = host(x, y + 1) - host(x, y - 1);
      if (gx * gx + gy * gy < 16.f) continue;
      for (int k = 0; k < kPatternSize; ++k)
        p.colors[k] = host(x + kPatternOffsets[k][0], y + kPatternOffsets[k][1]);
      points.push_back(p);
    }
  return points;
}

}  // namespace ldsm::test
