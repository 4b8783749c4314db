// Test scenes of the coarse-tracker tests: three textured planes at known depths, rendered by ray
// casting with a smooth analytic texture; the reference points carry exact inverse depths.
//   kRoomCorner: back wall, floor and left wall of a room seen from inside (no occlusions).
//   kOccludingPlanes: a back wall and two bounded, slanted planes in front of it (depth
//   discontinuities, so that points get occluded or disoccluded when the camera moves).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "camera/pyramid_camera.h"
#include "frontend/depth_map_pyramid.h"
#include "image/image_pyramid.h"
#include "ldsm/camera/calibration.h"
#include "ldsm/image.h"
#include "math/se3.h"

namespace ldsm::test {

struct ScenePlane {
  Eigen::Vector3d centre;
  Eigen::Vector3d e1, e2;  ///< orthonormal in-plane axes
  double half1, half2;     ///< half extents along e1, e2 (metres; large = unbounded)
  double phase;            ///< texture variation between planes
};

class TrackScene {
 public:
  static constexpr int kWidth = 320;
  static constexpr int kHeight = 240;
  static constexpr int kLevels = 5;

  enum class Layout { kRoomCorner, kOccludingPlanes };

  explicit TrackScene(Layout layout = Layout::kRoomCorner);

  PinholeIntrinsics intrinsics() const { return k_; }
  PyramidCamera camera() const { return PyramidCamera(k_, kLevels); }

  /// Renders the view of a camera with pose T_world_cam (the reference camera is the world):
  /// intensity, and inverse depth per pixel when `idepth` is not null. With `radial_k`, through
  /// the radial distortion of camera/radial_distortion.h: pixel = K D(x), D(x) = x (1 + k |x|^2).
  void render(const SE3d& T_world_cam, ImageF& image, ImageF* idepth, float radial_k = 0.f) const;

  /// Texture value (roughly 30..225) at in-plane coordinates (s, t) of a plane with `phase`.
  static double texture(double s, double t, double phase);

 private:
  PinholeIntrinsics k_;
  std::vector<ScenePlane> planes_;
};

/// Points with a strong gradient, the best of each block x block cell, with their inverse depth
/// read from `idepth` (exact at the pixel centre).
std::vector<DepthPoint> selectPoints(const ImageF& image, const ImageF& idepth, int block = 4,
                                     float min_gradient = 4.f);

/// A pyramid of `image` with TrackScene::kLevels levels.
ImagePyramid makePyramid(const ImageF& image);

/// Rotation angle (radians) and translation distance between two transforms.
double rotationError(const SE3d& a, const SE3d& b);
double translationError(const SE3d& a, const SE3d& b);

}  // namespace ldsm::test
