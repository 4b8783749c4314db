// Shared helpers of the synthetic-scene tests: scenes built once per test program, small camera
// options, FNV-1a checksums and an independent ray caster (Eigen, double precision).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <string>

#include "ldsm/drivers/sim/sim_scene.h"
#include "ldsm/image.h"
#include "ldsm/types.h"

namespace ldsm::drivers::sim::test {

/// The built-in scene `name`, built once per test program.
inline std::shared_ptr<const SimScene> sharedScene(const std::string& name) {
  static std::map<std::string, std::shared_ptr<const SimScene>> cache;
  auto it = cache.find(name);
  if (it == cache.end())
    it = cache.emplace(name, std::make_shared<const SimScene>(makeSimScene(name))).first;
  return it->second;
}

/// 64-bit FNV-1a over raw bytes.
inline std::uint64_t fnv1a(const void* data, std::size_t n,
                           std::uint64_t h = 1469598103934665603ull) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < n; ++i) {
    h ^= p[i];
    h *= 1099511628211ull;
  }
  return h;
}

template <typename T>
std::uint64_t fnv1a(const Image<T>& img, std::uint64_t h = 1469598103934665603ull) {
  for (int y = 0; y < img.height(); ++y)
    h = fnv1a(img.row(y), sizeof(T) * static_cast<std::size_t>(img.width()), h);
  return h;
}

inline Eigen::Vector3d toEigen(const Vec3& v) {
  return {v.x, v.y, v.z};
}

/// Nearest intersection of the world ray o + s d (s > 0) with the scene's quads, computed
/// independently of the renderer. Returns false when nothing is hit.
struct RayHit {
  int quad = -1;
  double s = std::numeric_limits<double>::infinity();
  double u = 0, v = 0;
  double edge_distance = 0;  ///< distance of the hit to the quad's border (metres)
};

inline RayHit castRay(const SimScene& scene, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  RayHit best;
  for (std::size_t i = 0; i < scene.quads.size(); ++i) {
    const SimQuad& q = scene.quads[i];
    const Eigen::Vector3d n = toEigen(q.normal()), p0 = toEigen(q.origin);
    const double denom = n.dot(d);
    if (std::abs(denom) < 1e-12) continue;
    const double s = n.dot(p0 - o) / denom;
    if (!(s > 1e-6) || s >= best.s) continue;
    const Eigen::Vector3d hit = o + s * d;
    const double u = toEigen(q.axis_u).dot(hit - p0), v = toEigen(q.axis_v).dot(hit - p0);
    if (u < 0 || v < 0 || u > q.size_u || v > q.size_v) continue;
    best.quad = static_cast<int>(i);
    best.s = s;
    best.u = u;
    best.v = v;
    best.edge_distance = std::min(std::min(u, q.size_u - u), std::min(v, q.size_v - v));
  }
  return best;
}

/// Distance from point p to the rectangle of quad q.
inline double distanceToQuad(const SimQuad& q, const Eigen::Vector3d& p) {
  const Eigen::Vector3d p0 = toEigen(q.origin), d = p - p0;
  const double u = std::clamp(toEigen(q.axis_u).dot(d), 0.0, q.size_u);
  const double v = std::clamp(toEigen(q.axis_v).dot(d), 0.0, q.size_v);
  return (p - (p0 + u * toEigen(q.axis_u) + v * toEigen(q.axis_v))).norm();
}

/// Rotation angle (radians) between two poses.
inline double rotationAngle(const Pose& a, const Pose& b) {
  return a.rotation.angularDistance(b.rotation);
}

}  // namespace ldsm::drivers::sim::test
