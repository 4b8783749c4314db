#include "init_scene.h"

#include <cmath>
#include <limits>

namespace ldsm::init_test {

namespace {

std::uint32_t mix(std::uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}

/// Lattice value in [0, 1) of integer point (i, j) for a seed.
double lattice(std::int64_t i, std::int64_t j, std::uint32_t seed) {
  const std::uint32_t h = mix(static_cast<std::uint32_t>(i) * 0x9e3779b1U ^
                              mix(static_cast<std::uint32_t>(j) + seed * 0x85ebca77U));
  return static_cast<double>(h >> 8) / static_cast<double>(1U << 24);
}

double fade(double x) {
  return x * x * x * (x * (x * 6.0 - 15.0) + 10.0);
}

/// Smooth value noise in [0, 1) with unit lattice spacing.
double valueNoise(double s, double t, std::uint32_t seed) {
  const double fs = std::floor(s), ft = std::floor(t);
  const auto i = static_cast<std::int64_t>(fs);
  const auto j = static_cast<std::int64_t>(ft);
  const double u = fade(s - fs), v = fade(t - ft);
  const double a = lattice(i, j, seed), b = lattice(i + 1, j, seed);
  const double c = lattice(i, j + 1, seed), d = lattice(i + 1, j + 1, seed);
  return (a + u * (b - a)) + v * ((c + u * (d - c)) - (a + u * (b - a)));
}

}  // namespace

void InitScene::addPlane(const Eigen::Vector3d& point, const Eigen::Vector3d& normal,
                         std::uint32_t seed) {
  InitPlane p;
  p.normal = normal.normalized();
  p.offset = p.normal.dot(point);
  const Eigen::Vector3d helper =
      std::abs(p.normal.y()) < 0.9 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitX();
  p.axis_s = helper.cross(p.normal).normalized();
  p.axis_t = p.normal.cross(p.axis_s);
  p.seed = seed;
  planes_.push_back(p);
}

double InitScene::intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                            int* plane) const {
  double best = std::numeric_limits<double>::infinity();
  int best_plane = -1;
  for (int i = 0; i < static_cast<int>(planes_.size()); ++i) {
    const InitPlane& p = planes_[static_cast<std::size_t>(i)];
    const double denom = p.normal.dot(dir);
    if (std::abs(denom) < 1e-12) continue;
    const double s = (p.offset - p.normal.dot(origin)) / denom;
    if (s > 1e-6 && s < best) {
      best = s;
      best_plane = i;
    }
  }
  if (plane != nullptr) *plane = best_plane;
  return best_plane < 0 ? -1.0 : best;
}

float InitScene::shade(int plane, const Eigen::Vector3d& X) const {
  const InitPlane& p = planes_[static_cast<std::size_t>(plane)];
  const double s = p.axis_s.dot(X);
  const double t = p.axis_t.dot(X);
  // Octaves with lattice spacings from 0.4 m down to 10 cm.
  double value = 0, total = 0, amplitude = 1, freq = 2.5 * texture_scale_;
  for (int o = 0; o < 3; ++o) {
    value += amplitude * valueNoise(s * freq, t * freq, p.seed + 101U * static_cast<unsigned>(o));
    total += amplitude;
    amplitude *= 0.8;
    freq *= 2.0;
  }
  return static_cast<float>(30.0 + 195.0 * value / total);
}

ImageF InitScene::render(const SE3d& T_world_cam, const PinholeIntrinsics& K, int samples,
                         float noise, std::mt19937* rng) const {
  ImageF image(K.width, K.height);
  const Eigen::Matrix3d R = T_world_cam.rotationMatrix();
  const Eigen::Vector3d origin = T_world_cam.translation();
  std::normal_distribution<float> gauss(0.f, 1.f);
  const double step = 1.0 / samples;
  for (int y = 0; y < K.height; ++y) {
    for (int x = 0; x < K.width; ++x) {
      double sum = 0;
      for (int sy = 0; sy < samples; ++sy) {
        for (int sx = 0; sx < samples; ++sx) {
          const double u = x - 0.5 + (sx + 0.5) * step;
          const double v = y - 0.5 + (sy + 0.5) * step;
          const Eigen::Vector3d dir = R * Eigen::Vector3d((u - K.cx) / K.fx, (v - K.cy) / K.fy, 1);
          int plane = -1;
          const double s = intersect(origin, dir, &plane);
          sum += plane < 0 ? 128.0 : shade(plane, origin + s * dir);
        }
      }
      float value = static_cast<float>(sum / (samples * samples));
      if (noise > 0.f && rng != nullptr) value += noise * gauss(*rng);
      image(x, y) = value;
    }
  }
  return image;
}

double InitScene::inverseDepth(const SE3d& T_world_cam, const PinholeIntrinsics& K, double u,
                               double v) const {
  const Eigen::Vector3d ray((u - K.cx) / K.fx, (v - K.cy) / K.fy, 1);  // camera frame, z = 1
  const double s =
      intersect(T_world_cam.translation(), T_world_cam.rotationMatrix() * ray, nullptr);
  return s > 0 ? 1.0 / s : 0.0;  // the hit is at camera depth z = s
}

InitScene wallAndFloorScene(double texture_scale) {
  InitScene scene(texture_scale);
  const double a = 25.0 * 3.14159265358979323846 / 180.0;
  scene.addPlane({0, 0, 4.0}, {std::sin(a), 0, -std::cos(a)}, 11U);
  scene.addPlane({0, 1.2, 0}, {0, -1, 0}, 23U);
  return scene;
}

}  // namespace ldsm::init_test
