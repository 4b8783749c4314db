// The keyframe the tracker aligns new frames to, as the mapping hands it over: its id, pose,
// exposure, affine brightness and image pyramid (owned by the window, alive while it is the
// reference).
#pragma once

#include "image/image_pyramid.h"
#include "math/se3.h"
#include "model/affine_light.h"

namespace ldsm {

struct TrackingReference {
  int keyframe_id = -1;
  std::int64_t frame_index = -1;
  SE3d T_c_w;  ///< world -> camera
  double exposure = 1.0;
  AffineLight aff;
  const ImagePyramid* pyramid = nullptr;
};

}  // namespace ldsm
