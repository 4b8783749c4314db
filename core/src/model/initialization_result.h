// What a finished monocular initialisation hands to the mapping: the reference frame's points with
// inverse depths, and the last frame's pose and brightness relative to the reference.
#pragma once

#include <vector>

#include "math/se3.h"
#include "model/affine_light.h"

namespace ldsm {

/// A reference point of the finished initialisation (level-0 pixel coordinates).
struct InitializedPoint {
  float u = 0, v = 0;
  float idepth = 1;   ///< inverse depth in the reference frame (mean over the map = 1)
  float hessian = 0;  ///< photometric Hessian of the inverse depth (information; 0: unknown)
  bool good = false;  ///< an inlier in the last frame
  bool is_corner = false;
};

struct InitializationResult {
  std::vector<InitializedPoint> points;
  SE3d T_frame_ref;          ///< reference -> last frame (translation in the map's scale)
  AffineLight affine_frame;  ///< last frame's affine brightness relative to the reference (0, 0)
  double exposure_ref = 1;
  double exposure_frame = 1;
  int frames = 0;  ///< frames tracked after the reference
};

}  // namespace ldsm
