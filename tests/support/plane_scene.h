// A tiny analytic scene for engine unit tests: textured planes rendered by ray casting, with exact
// inverse depth per pixel. Smooth texture (sums of sinusoids and soft blobs) so that image
// gradients are informative at every scale.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <vector>

#include "ldsm/image.h"

namespace ldsm::test {

struct TexturedPlane {
  Eigen::Vector3d point;           ///< a point on the plane (world)
  Eigen::Vector3d normal;          ///< unit normal
  Eigen::Vector3d u_axis, v_axis;  ///< texture axes in the plane
  double phase = 0.0;
};

class PlaneScene {
 public:
  /// A wall at z = `distance` facing the camera, plus a tilted floor, in front of the origin.
  static PlaneScene wallAndFloor(double distance = 4.0) {
    PlaneScene s;
    s.planes_.push_back({{0, 0, distance}, {0, 0, -1}, {1, 0, 0}, {0, 1, 0}, 0.3});
    s.planes_.push_back({{0, 1.2, 0}, {0, -1, 0}, {1, 0, 0}, {0, 0, 1}, 1.7});
    return s;
  }

  /// Texture value in [20, 235] at plane coordinates (x, y) in metres.
  static double texture(double x, double y, double phase) {
    double v = 0.0;
    v += 0.35 * std::sin(3.1 * x + phase) * std::cos(2.3 * y - 0.5 * phase);
    v += 0.25 * std::sin(7.3 * x + 4.1 * y + 2 * phase);
    v += 0.20 * std::cos(11.7 * x - 6.2 * y + phase);
    v += 0.15 * std::sin(17.9 * y + 0.7 * x);
    return 127.5 + 100.0 * v;
  }

  /// Renders a pinhole image (fx, fy, cx, cy) seen from camera-to-world pose T_w_c; optionally
  /// writes the inverse depth of every pixel (0 where no plane is hit).
  ImageF render(const Eigen::Isometry3d& T_w_c, double fx, double fy, double cx, double cy, int w,
                int h, ImageF* idepth = nullptr) const {
    ImageF img(w, h, 0.f);
    if (idepth) idepth->resize(w, h);
    const Eigen::Matrix3d R = T_w_c.linear();
    const Eigen::Vector3d o = T_w_c.translation();
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const Eigen::Vector3d ray_c((x - cx) / fx, (y - cy) / fy, 1.0);
        const Eigen::Vector3d dir = R * ray_c;
        double best = std::numeric_limits<double>::infinity();
        double value = 0.0;
        for (const auto& p : planes_) {
          const double den = p.normal.dot(dir);
          if (std::fabs(den) < 1e-9) continue;
          const double s = p.normal.dot(p.point - o) / den;  // depth along z of the camera ray
          if (s <= 0.05 || s >= best) continue;
          best = s;
          const Eigen::Vector3d hit = o + s * dir - p.point;
          value = texture(hit.dot(p.u_axis), hit.dot(p.v_axis), p.phase);
        }
        img(x, y) = static_cast<float>(value);
        if (idepth) (*idepth)(x, y) = std::isfinite(best) ? static_cast<float>(1.0 / best) : 0.f;
      }
    return img;
  }

 private:
  std::vector<TexturedPlane> planes_;
};

}  // namespace ldsm::test
