// A procedural test scene for the initializer: textured planes ray-cast by a pinhole camera, with
// smooth multi-octave value-noise textures, supersampled, plus optional Gaussian noise. Gives the
// true inverse depth of every pixel.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <random>
#include <vector>

#include "ldsm/camera/calibration.h"
#include "ldsm/image.h"
#include "math/se3.h"

namespace ldsm::init_test {

struct InitPlane {
  Eigen::Vector3d normal;  ///< unit normal; the plane is { X : normal . X = offset }
  double offset = 0;
  Eigen::Vector3d axis_s;  ///< in-plane texture axes (unit, orthogonal to the normal)
  Eigen::Vector3d axis_t;
  std::uint32_t seed = 1;
};

class InitScene {
 public:
  /// Texture frequency multiplier (1: lattice spacings 0.4 m .. 0.1 m; smaller is smoother).
  explicit InitScene(double texture_scale = 1.0) : texture_scale_(texture_scale) {}

  /// Adds the plane through `point` with normal `normal` (normalised here).
  void addPlane(const Eigen::Vector3d& point, const Eigen::Vector3d& normal, std::uint32_t seed);

  /// The nearest plane hit along the ray from `origin` in direction `dir` (world); returns the
  /// hit distance in units of |dir|, or a negative value when nothing is hit.
  double intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, int* plane) const;

  /// Texture value (grey levels, about 30..225) of the plane at world point X.
  float shade(int plane, const Eigen::Vector3d& X) const;

  /// Renders the view of camera pose T_world_cam (camera-to-world; x right, y down, z forward)
  /// with `samples` x `samples` supersampling, adding Gaussian noise of sigma `noise` (grey).
  ImageF render(const SE3d& T_world_cam, const PinholeIntrinsics& K, int samples, float noise,
                std::mt19937* rng) const;

  /// True inverse depth (1/z in the camera) of pixel (u, v); 0 when the ray hits nothing.
  double inverseDepth(const SE3d& T_world_cam, const PinholeIntrinsics& K, double u,
                      double v) const;

 private:
  double texture_scale_;
  std::vector<InitPlane> planes_;
};

/// A wall about 4 m ahead (tilted by 25 degrees about the vertical) and a floor 1.2 m below the
/// camera at the origin: inverse depths between ~0.15 and ~0.4 over the image.
InitScene wallAndFloorScene(double texture_scale = 1.0);

}  // namespace ldsm::init_test
