// A small synthetic sequence for the mapping tests: the wall-and-floor planes seen by a camera
// moving sideways, every frame rendered with its exact inverse depth, and an initialisation result
// made from the truth (the reference frame's gradient pixels with their true inverse depths), so
// the Mapper and the mapping stage can be driven without the frontend.
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <memory>
#include <vector>

#include "camera/pyramid_camera.h"
#include "image/pyramid_pool.h"
#include "math/se3.h"
#include "model/initialization_result.h"
#include "plane_scene.h"

namespace ldsm::test {

class SyntheticWindow {
 public:
  static constexpr int kW = 320, kH = 240, kLevels = 4;
  static constexpr double kF = 260.0, kCx = 159.5, kCy = 119.5;

  explicit SyntheticWindow(int frames, double step = 0.04)
      : camera_(PinholeIntrinsics{kF, kF, kCx, kCy, kW, kH}, kLevels),
        pool_(kW, kH, kLevels),
        scene_(PlaneScene::wallAndFloor(4.0)) {
    for (int i = 0; i < frames; ++i) {
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.translation() = Eigen::Vector3d(step * i, 0.2 * step * i, 0.5 * step * i);
      T.linear() = Eigen::AngleAxisd(0.004 * i, Eigen::Vector3d::UnitY()).toRotationMatrix();
      T_w_c_.push_back(T);
      images_.push_back(scene_.render(T, kF, kF, kCx, kCy, kW, kH, i == 0 ? &idepth0_ : nullptr));
    }
  }

  const PyramidCamera& camera() const { return camera_; }
  PyramidPool& pool() { return pool_; }
  int frames() const { return static_cast<int>(images_.size()); }

  /// World -> camera pose of frame i (world = frame 0's camera).
  SE3d T_c_w(int i) const {
    const Eigen::Isometry3d T = T_w_c_[i].inverse();
    return SE3d(Eigen::Matrix3d(T.linear()), Eigen::Vector3d(T.translation()));
  }

  /// Frame i as a pyramid from the pool.
  std::unique_ptr<ImagePyramid> pyramid(int i) {
    std::unique_ptr<ImagePyramid> p = pool_.acquire();
    p->build(images_[i].view());
    return p;
  }

  /// The initialisation a perfect initializer would hand over for reference 0 and frame `last`.
  InitializationResult initialization(int last) const {
    InitializationResult r;
    for (int y = 6; y < kH - 6; y += 3)
      for (int x = 6; x < kW - 6; x += 3) {
        const ImageF& img = images_[0];
        const float gx = img(x + 1, y) - img(x - 1, y), gy = img(x, y + 1) - img(x, y - 1);
        if (gx * gx + gy * gy < 100.f || !(idepth0_(x, y) > 0.f)) continue;
        InitializedPoint p;
        p.u = static_cast<float>(x);
        p.v = static_cast<float>(y);
        p.idepth = idepth0_(x, y);
        p.hessian = 1e3f;
        p.good = true;
        r.points.push_back(p);
      }
    r.T_frame_ref = T_c_w(last);
    r.frames = last;
    return r;
  }

 private:
  PyramidCamera camera_;
  PyramidPool pool_;
  PlaneScene scene_;
  std::vector<Eigen::Isometry3d> T_w_c_;
  std::vector<ImageF> images_;
  ImageF idepth0_;
};

/// Rotation (radians) and translation (metres) between two world -> camera poses.
inline Eigen::Vector2d poseError(const SE3d& a, const SE3d& b) {
  const SE3d d = a * b.inverse();
  return {d.so3().log().norm(), (a.inverse().translation() - b.inverse().translation()).norm()};
}

}  // namespace ldsm::test
