// A residual radial distortion of the rectified images (the online calibration refinement of the
// window, backend/calibration_refinement.h): a ray with pinhole coordinates x = (X/Z, Y/Z) appears
// in the image at normalized coordinates x (1 + k |x|^2). k = 0 is the plain pinhole.
#pragma once

#include <Eigen/Core>

#include "camera/pyramid_camera.h"

namespace ldsm {

/// Image normalized coordinates of the ray with pinhole coordinates (x, y).
inline Eigen::Vector2f applyRadial(float k, float x, float y) {
  const float f = 1.f + k * (x * x + y * y);
  return {x * f, y * f};
}

/// Pinhole coordinates of image normalized coordinates (x, y): applyRadial's inverse. Newton's
/// method on the radial scale t (t (1 + k R^2 t^2) = 1 with R = |(x, y)|), from t = 1; defined
/// while 1 + 3 k r^2 > 0 (for k < 0: inside the radius where the distortion turns back).
inline Eigen::Vector2f removeRadial(float k, float x, float y) {
  const float kr2 = k * (x * x + y * y);
  float t = 1.f;
  for (int it = 0; it < 4; ++it) {
    const float kt2 = kr2 * t * t;
    t -= (t * (1.f + kt2) - 1.f) / (1.f + 3.f * kt2);
  }
  return {x * t, y * t};
}

/// The ray (z = 1) through image pixel (u, v) of `cam` with the radial distortion k.
inline Eigen::Vector3f radialRay(const LevelCamera& cam, float k, float u, float v) {
  const Eigen::Vector2f x = removeRadial(k, cam.fxi * u + cam.cxi, cam.fyi * v + cam.cyi);
  return {x.x(), x.y(), 1.f};
}

/// The image pixel of camera-frame point q (q.z > 0) with the radial distortion k.
inline Eigen::Vector2f radialProject(const LevelCamera& cam, float k, const Eigen::Vector3f& q) {
  const Eigen::Vector2f x = applyRadial(k, q.x() / q.z(), q.y() / q.z());
  return {cam.fx * x.x() + cam.cx, cam.fy * x.y() + cam.cy};
}

}  // namespace ldsm
