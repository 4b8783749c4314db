// Synthetic map keyframes for the map-reuse tests (reactivation search, redundancy): a camera of
// 320x240 pixels looking at a gently curved surface about 4 m away. A map keyframe hosts points
// on a pixel grid and corners at random pixels with random ORB descriptors, all with their true
// inverse depths; a view of the same scene from another pose sees those corners where they
// project, with a few descriptor bits flipped. Pure geometry: nothing is rendered.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "camera/pyramid_camera.h"
#include "math/se3.h"
#include "model/marginalized_keyframe.h"
#include "reuse/reactivation_search.h"

namespace ldsm::test {

constexpr int kReuseW = 320, kReuseH = 240;
constexpr float kReuseBorder = 4.f;  // the margin the reuse checks keep from the image border

inline LevelCamera reuseCamera() {
  return PyramidCamera(PinholeIntrinsics{260.0, 260.0, 159.5, 119.5, kReuseW, kReuseH}, 1)[0];
}

/// Camera-to-world pose: centre `c`, turned `yaw_deg` about the vertical (y) axis.
inline SE3d cameraAt(const Eigen::Vector3d& c, double yaw_deg = 0.0) {
  return SE3d(SO3d::exp(Eigen::Vector3d(0.0, yaw_deg * 3.14159265358979323846 / 180.0, 0.0)), c);
}

/// Depth of the scene along pixel (u, v) of a map keyframe (3.5 .. 4.5 m).
inline double sceneDepth(double u, double v) {
  return 4.0 + 0.5 * std::sin(0.031 * u) * std::cos(0.027 * v);
}

inline OrbDescriptor randomDescriptor(std::mt19937_64& rng) {
  return {rng(), rng(), rng(), rng()};
}

/// `d` with `bits` random bits flipped (a bit may be drawn twice).
inline OrbDescriptor flipBits(OrbDescriptor d, int bits, std::mt19937_64& rng) {
  for (int k = 0; k < bits; ++k) {
    const auto b = static_cast<unsigned>(rng() % 256);
    d[b / 64] ^= std::uint64_t{1} << (b % 64);
  }
  return d;
}

/// World point of host pixel (u, v) with inverse depth `idepth` of a keyframe at T_w_c and scale.
inline Eigen::Vector3d hostToWorld(const LevelCamera& cam, const SE3d& T_w_c, double scale, float u,
                                   float v, float idepth) {
  const Eigen::Vector3d ray = cam.unproject(u, v).cast<double>();
  return T_w_c * (scale * ray / static_cast<double>(idepth));
}

/// Pinhole projection into a camera at T_c_w; false when behind it or outside the checked area.
inline bool projectTo(const LevelCamera& cam, const SE3d& T_c_w, const Eigen::Vector3d& X_w,
                      Eigen::Vector2f* px) {
  const Eigen::Vector3d X = T_c_w * X_w;
  if (!(X.z() > 1e-6)) return false;
  *px = cam.project(X.cast<float>());
  return px->x() >= kReuseBorder && px->y() >= kReuseBorder &&
         px->x() <= static_cast<float>(cam.width) - 1.f - kReuseBorder &&
         px->y() <= static_cast<float>(cam.height) - 1.f - kReuseBorder;
}

/// A map keyframe at camera-to-world pose T_w_c (in the map's units, scale 1): points every
/// `step` pixels and `corners` corners with descriptors. `idepth_scale` divides the stored
/// inverse depths' units (a keyframe whose map was later scaled by that factor).
inline MarginalizedKeyframe mapKeyframe(int id, const SE3d& T_w_c, std::mt19937_64& rng,
                                        int corners = 120, int step = 8,
                                        double idepth_scale = 1.0) {
  MarginalizedKeyframe kf;
  kf.id = id;
  kf.T_w_c = T_w_c;
  kf.newest_when_left = id + 7;
  kf.path_length = 0.5 * id;
  for (int y = step; y < kReuseH - step; y += step)
    for (int x = step; x < kReuseW - step; x += step) {
      PatchPoint p;
      p.u = static_cast<float>(x);
      p.v = static_cast<float>(y);
      p.idepth = static_cast<float>(idepth_scale / sceneDepth(x, y));
      kf.points.push_back(p);
    }
  std::uniform_real_distribution<float> ux(20.f, kReuseW - 21.f), uy(20.f, kReuseH - 21.f);
  for (int i = 0; i < corners; ++i) {
    const Eigen::Vector2f c(ux(rng), uy(rng));
    kf.corners.push_back(c);
    kf.corner_idepth.push_back(static_cast<float>(idepth_scale / sceneDepth(c.x(), c.y())));
    kf.descriptors.push_back(randomDescriptor(rng));
  }
  return kf;
}

/// How many of the keyframe's points (at pose record T_w_c, scale) a camera at T_c_w sees.
inline int pointsSeen(const MarginalizedKeyframe& kf, const SE3d& T_w_c, double scale,
                      const SE3d& T_c_w) {
  const LevelCamera cam = reuseCamera();
  int n = 0;
  Eigen::Vector2f px;
  for (const PatchPoint& p : kf.points)
    n += projectTo(cam, T_c_w, hostToWorld(cam, T_w_c, scale, p.u, p.v, p.idepth), &px) ? 1 : 0;
  return n;
}

/// Adds to `view` the corners of `kf` (true pose T_w_c) that the camera at `T_c_true` sees, with
/// `flips` descriptor bits flipped, and `clutter` unrelated corners. The view's own pose is left
/// as it is (a test may give it a wrong one).
inline void addCornersSeen(ReuseView& view, const MarginalizedKeyframe& kf, const SE3d& T_w_c,
                           const SE3d& T_c_true, std::mt19937_64& rng, int flips = 6,
                           int clutter = 0) {
  std::normal_distribution<float> noise(0.f, 0.3f);
  for (std::size_t i = 0; i < kf.corners.size(); ++i) {
    const Eigen::Vector3d X_w = hostToWorld(view.camera, T_w_c, 1.0, kf.corners[i].x(),
                                            kf.corners[i].y(), kf.corner_idepth[i]);
    Eigen::Vector2f px;
    if (!projectTo(view.camera, T_c_true, X_w, &px)) continue;
    view.corners.push_back(px + Eigen::Vector2f(noise(rng), noise(rng)));
    view.descriptors.push_back(flipBits(kf.descriptors[i], flips, rng));
  }
  std::uniform_real_distribution<float> ux(20.f, kReuseW - 21.f), uy(20.f, kReuseH - 21.f);
  for (int i = 0; i < clutter; ++i) {
    view.corners.emplace_back(ux(rng), uy(rng));
    view.descriptors.push_back(randomDescriptor(rng));
  }
}

/// The newest keyframe (id 60, far along the path: any map keyframe with id < 40 is a revisit)
/// at camera-to-world pose T_w_c, without corners.
inline ReuseView viewAt(const SE3d& T_w_c) {
  ReuseView view;
  view.keyframe_id = 60;
  view.T_c_w = T_w_c.inverse();
  view.camera = reuseCamera();
  view.median_depth = 4.0;
  view.path_length = 100.0;
  view.window_ids = {57, 58, 59, 60};
  return view;
}

}  // namespace ldsm::test
