#include "track_scene.h"

#include <cmath>
#include <limits>

#include "camera/radial_distortion.h"

namespace ldsm::test {

TrackScene::TrackScene(Layout layout) {
  k_.fx = 250;
  k_.fy = 250;
  k_.cx = 159.5;
  k_.cy = 119.5;
  k_.width = kWidth;
  k_.height = kHeight;
  const double big = 1e3;
  if (layout == Layout::kRoomCorner) {
    // Back wall at z = 5; a left wall (x = z - 6) and a floor (y = 0.8 + 0.7 (5 - z)) turned 45
    // and 35 degrees towards the camera, which sees them from inside.
    planes_.push_back({{0, 0, 5}, {1, 0, 0}, {0, 1, 0}, big, big, 0.0});
    planes_.push_back(
        {{-1, 0, 5}, Eigen::Vector3d(1, 0, 1).normalized(), {0, 1, 0}, big, big, 2.9});
    planes_.push_back(
        {{0, 0.8, 5}, {1, 0, 0}, Eigen::Vector3d(0, -0.7, 1).normalized(), big, big, 1.3});
    return;
  }
  // Back wall at z = 6.
  planes_.push_back({{0, 0, 6}, {1, 0, 0}, {0, 1, 0}, big, big, 0.0});
  // A plane on the left, turned about the vertical axis, about 3 m away.
  planes_.push_back(
      {{-1.0, -0.1, 3.0}, Eigen::Vector3d(1, 0, 0.6).normalized(), {0, 1, 0}, 0.9, 1.1, 1.3});
  // A plane at the lower right, tilted back like a ramp, about 3.5 m away.
  planes_.push_back(
      {{0.9, 0.6, 3.5}, {1, 0, 0}, Eigen::Vector3d(0, 0.7, 1).normalized(), 0.8, 1.0, 2.9});
}

double TrackScene::texture(double s_metres, double t_metres, double phase) {
  const double s = s_metres, t = t_metres;
  double v = 0.0;
  v += 0.30 * std::sin(2.9 * s + phase) * std::cos(2.1 * t - 0.5 * phase);
  v += 0.22 * std::sin(6.7 * s + 3.9 * t + 2.0 * phase);
  v += 0.18 * std::cos(10.3 * s - 6.1 * t + phase);
  v += 0.14 * std::sin(15.1 * t + 1.7 * s - phase);
  v += 0.10 * std::cos(19.7 * s + 9.1 * t + 0.3 * phase);
  return 127.5 + 100.0 * v;
}

void TrackScene::render(const SE3d& T_world_cam, ImageF& image, ImageF* idepth,
                        float radial_k) const {
  image.resize(kWidth, kHeight);
  if (idepth != nullptr) idepth->resize(kWidth, kHeight);
  const Eigen::Matrix3d R = T_world_cam.rotationMatrix();
  const Eigen::Vector3d o = T_world_cam.translation();
  // Nearest hit along the ray through (x, y): the texture value and the camera z of the hit.
  const auto castRay = [&](double x, double y, double& z_hit) {
    Eigen::Vector2d m((x - k_.cx) / k_.fx, (y - k_.cy) / k_.fy);
    if (radial_k != 0.f)
      m = removeRadial(radial_k, static_cast<float>(m.x()), static_cast<float>(m.y()))
              .cast<double>();
    const Eigen::Vector3d dir = R * Eigen::Vector3d(m.x(), m.y(), 1.0);
    z_hit = std::numeric_limits<double>::infinity();
    double value = 0.0;
    for (const ScenePlane& p : planes_) {
      const Eigen::Vector3d n = p.e1.cross(p.e2);
      const double den = n.dot(dir);
      if (std::abs(den) < 1e-12) continue;
      const double z = n.dot(p.centre - o) / den;  // the camera z of the hit (ray has z = 1)
      if (z <= 0.05 || z >= z_hit) continue;
      const Eigen::Vector3d d = o + z * dir - p.centre;
      const double s = d.dot(p.e1);
      const double t = d.dot(p.e2);
      if (std::abs(s) > p.half1 || std::abs(t) > p.half2) continue;
      z_hit = z;
      value = texture(s, t, p.phase);
    }
    return value;
  };
  // Each pixel integrates its area (2 x 2 samples), as a camera pixel does; inverse depth is
  // taken at the pixel centre.
  constexpr int kSub = 2;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      double sum = 0.0, z = 0.0;
      for (int sy = 0; sy < kSub; ++sy) {
        for (int sx = 0; sx < kSub; ++sx) {
          sum += castRay(x + (sx + 0.5) / kSub - 0.5, y + (sy + 0.5) / kSub - 0.5, z);
        }
      }
      image(x, y) = static_cast<float>(sum / (kSub * kSub));
      if (idepth != nullptr) {
        castRay(x, y, z);
        (*idepth)(x, y) = std::isfinite(z) ? static_cast<float>(1.0 / z) : 0.f;
      }
    }
  }
}

std::vector<DepthPoint> selectPoints(const ImageF& image, const ImageF& idepth, int block,
                                     float min_gradient) {
  std::vector<DepthPoint> points;
  for (int by = 2; by + block <= image.height() - 2; by += block) {
    for (int bx = 2; bx + block <= image.width() - 2; bx += block) {
      float best = min_gradient * min_gradient;
      int best_x = -1, best_y = -1;
      for (int y = by; y < by + block; ++y) {
        for (int x = bx; x < bx + block; ++x) {
          const float gx = 0.5f * (image(x + 1, y) - image(x - 1, y));
          const float gy = 0.5f * (image(x, y + 1) - image(x, y - 1));
          const float g2 = gx * gx + gy * gy;
          if (g2 > best && idepth(x, y) > 0.f) {
            best = g2;
            best_x = x;
            best_y = y;
          }
        }
      }
      if (best_x < 0) continue;
      DepthPoint p;
      p.u = static_cast<float>(best_x);
      p.v = static_cast<float>(best_y);
      p.idepth = idepth(best_x, best_y);
      p.weight = 1.f;
      points.push_back(p);
    }
  }
  return points;
}

ImagePyramid makePyramid(const ImageF& image) {
  ImagePyramid pyramid(image.width(), image.height(), TrackScene::kLevels);
  pyramid.build(image.view());
  return pyramid;
}

double rotationError(const SE3d& a, const SE3d& b) {
  return (a.so3().inverse() * b.so3()).angle();
}

double translationError(const SE3d& a, const SE3d& b) {
  return (a.translation() - b.translation()).norm();
}

}  // namespace ldsm::test
