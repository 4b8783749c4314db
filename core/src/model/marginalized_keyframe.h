// A keyframe as it leaves the optimisation window, handed on as a value (to loop closure, and to
// whatever keeps the map): its final pose and brightness, the points it hosted with their final
// depths and pattern intensities, its corners with depths (for ORB descriptors and PnP), and its
// level-0 image for describing it. Nothing in it refers back into the window.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "ldsm/image.h"
#include "ldsm/math/se3.h"
#include "model/affine_light.h"
#include "model/patch_point.h"

namespace ldsm {

struct MarginalizedKeyframe {
  int id = -1;
  std::int64_t frame_index = 0;
  double timestamp = 0.0;
  double exposure = 1.0;  ///< exposure time (1 when unknown)
  AffineLight aff;
  SE3d T_w_c;                            ///< camera-to-world, the window's final estimate
  float radial_k = 0.f;                  ///< residual radial distortion the window applied
  std::vector<PatchPoint> points;        ///< hosted points with a converged depth
  std::vector<Eigen::Vector2f> corners;  ///< level-0 corner pixels (ORB is computed there)
  std::vector<float> corner_idepth;      ///< per corner, NaN: unknown
  ImageF image;                          ///< level-0 intensity (photometrically corrected)
};

}  // namespace ldsm
