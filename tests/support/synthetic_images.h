// Procedural test images for point selection and epipolar tracing: smooth value-noise texture,
// anti-aliased checkerboards and squares, and a textured plane seen by a pinhole camera.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <functional>

#include "camera/pyramid_camera.h"
#include "image/image_pyramid.h"
#include "ldsm/image.h"
#include "math/se3.h"

namespace ldsm::test {

/// A well-mixed 32-bit hash of integer lattice coordinates.
inline std::uint32_t latticeHash(std::int32_t x, std::int32_t y, std::uint32_t seed) {
  std::uint32_t h = seed * 0x9E3779B9u ^ static_cast<std::uint32_t>(x) * 0x85EBCA6Bu ^
                    static_cast<std::uint32_t>(y) * 0xC2B2AE35u;
  h ^= h >> 16;
  h *= 0x7FEB352Du;
  h ^= h >> 15;
  h *= 0x846CA68Bu;
  h ^= h >> 16;
  return h;
}

/// Value noise in [0, 1] with lattice spacing 1 and a C2 (quintic) blend between lattice values.
inline double valueNoise(double x, double y, std::uint32_t seed) {
  const double fx = std::floor(x), fy = std::floor(y);
  const auto ix = static_cast<std::int32_t>(fx), iy = static_cast<std::int32_t>(fy);
  auto fade = [](double t) { return t * t * t * (t * (t * 6 - 15) + 10); };
  const double tx = fade(x - fx), ty = fade(y - fy);
  auto v = [&](int dx, int dy) { return latticeHash(ix + dx, iy + dy, seed) / 4294967295.0; };
  const double top = v(0, 0) + tx * (v(1, 0) - v(0, 0));
  const double bottom = v(0, 1) + tx * (v(1, 1) - v(0, 1));
  return top + ty * (bottom - top);
}

/// Smooth multi-scale texture in grey levels (about 30..225); `feature` is the coarsest lattice
/// spacing in the units of (x, y).
inline double texture(double x, double y, double feature, std::uint32_t seed = 1) {
  const double t = 0.5 * valueNoise(x / feature, y / feature, seed) +
                   0.3 * valueNoise(2 * x / feature, 2 * y / feature, seed + 17) +
                   0.2 * valueNoise(4 * x / feature, 4 * y / feature, seed + 31);
  return 30.0 + 195.0 * t;
}

/// An image whose pixel (x, y) has value f(x, y).
inline ImageF renderImage(int w, int h, const std::function<double(double, double)>& f) {
  ImageF img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img(x, y) = static_cast<float>(f(x, y));
  return img;
}

/// f averaged over a 4x4 grid of sub-pixel samples of each pixel (anti-aliasing).
inline ImageF renderSupersampled(int w, int h, const std::function<double(double, double)>& f) {
  return renderImage(w, h, [&](double x, double y) {
    double sum = 0;
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) sum += f(x - 0.375 + 0.25 * i, y - 0.375 + 0.25 * j);
    return sum / 16.0;
  });
}

/// Checkerboard of `square`-pixel squares whose corners lie at (ox + i square, oy + j square).
inline double checkerboard(double x, double y, double square, double ox, double oy) {
  const auto i = static_cast<long>(std::floor((x - ox) / square));
  const auto j = static_cast<long>(std::floor((y - oy) / square));
  return ((i + j) & 1) ? 200.0 : 50.0;
}

/// Deterministic zero-mean noise with standard deviation ~sigma (sum of uniforms).
inline double pixelNoise(int x, int y, double sigma, std::uint32_t seed = 7) {
  double s = 0;
  for (std::uint32_t k = 0; k < 4; ++k) s += latticeHash(x, y, seed + k) / 4294967295.0 - 0.5;
  return s * sigma * std::sqrt(3.0);  // var of the sum = 4 / 12
}

inline ImagePyramid makePyramid(const ImageF& img, int levels) {
  ImagePyramid pyr(img.width(), img.height(), levels);
  pyr.build(img.view());
  return pyr;
}

/// A textured plane n . X = d (world frame) and a pinhole camera; renders views and gives the
/// ground-truth inverse depth of every pixel.
struct PlaneScene {
  Eigen::Vector3d normal = Eigen::Vector3d(0.0, -0.25, 1.0).normalized();
  double distance = 3.0;
  double texels_per_metre = 8.0;  ///< coarsest texture lattice: one value every 12.5 cm
  PinholeIntrinsics intrinsics{300.0, 300.0, 159.5, 119.5, 320, 240};

  LevelCamera camera() const { return PyramidCamera(intrinsics, 1)[0]; }

  /// Distance along the camera ray K^-1 (x, y, 1) (so depth z) to the plane; camera-to-world pose.
  double depth(const SE3d& T_w_c, double x, double y) const {
    const Eigen::Vector3d ray((x - intrinsics.cx) / intrinsics.fx,
                              (y - intrinsics.cy) / intrinsics.fy, 1.0);
    const Eigen::Vector3d ray_w = T_w_c.rotationMatrix() * ray;
    return (distance - normal.dot(T_w_c.translation())) / normal.dot(ray_w);
  }

  double intensity(const SE3d& T_w_c, double x, double y) const {
    const Eigen::Vector3d ray((x - intrinsics.cx) / intrinsics.fx,
                              (y - intrinsics.cy) / intrinsics.fy, 1.0);
    const Eigen::Vector3d X = T_w_c * (depth(T_w_c, x, y) * ray);
    // Texture coordinates in a basis of the plane.
    const Eigen::Vector3d e1 = Eigen::Vector3d::UnitX().cross(normal).cross(normal).normalized();
    const Eigen::Vector3d e2 = normal.cross(e1);
    return texture(texels_per_metre * e1.dot(X), texels_per_metre * e2.dot(X), 1.0, 5);
  }

  ImageF render(const SE3d& T_w_c) const {
    return renderImage(intrinsics.width, intrinsics.height,
                       [&](double x, double y) { return intensity(T_w_c, x, y); });
  }
};

}  // namespace ldsm::test
