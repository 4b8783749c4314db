// A point as the map keeps it once its host keyframe has left the optimisation window: the
// host pixel, the inverse depth the window settled on, and the host's intensities over the
// residual pattern (photometrically corrected, level 0). That is everything a photometric
// alignment of the host to another image needs (loop-constraint refinement, relocalisation).
#pragma once

#include <cstdint>

#include "model/residual_pattern.h"

namespace ldsm {

struct PatchPoint {
  float u = 0.f, v = 0.f;                 ///< level-0 pixel in the host keyframe
  float idepth = 0.f;                     ///< inverse depth in the host keyframe (> 0)
  float idepth_hessian = 0.f;             ///< the window's last J_d^T W J_d of the inverse depth
  float colors[kPatternSize] = {};        ///< host intensities of the pattern
  float grad_weights[kPatternSize] = {};  ///< c^2 / (c^2 + |grad I_host|^2), square-rooted
  int observations = 0;  ///< inlier residuals (other keyframes) when it left the window
  bool is_corner = false;
};

}  // namespace ldsm
