#include "backend/active_point.h"

#include <cmath>

#include "backend/window_keyframe.h"
#include "image/compact_plane.h"
#include "image/interpolation.h"

namespace ldsm {

PatchPoint toPatchPoint(const ActivePoint& point) {
  PatchPoint out;
  out.u = point.u;
  out.v = point.v;
  out.idepth = point.idepth;
  out.idepth_hessian = point.hessian_idepth;
  for (int k = 0; k < kPatternSize; ++k) {
    out.colors[k] = point.colors[k];
    out.grad_weights[k] = point.grad_weights[k];
  }
  out.observations = point.inlier_residuals;
  out.is_corner = point.is_corner;
  return out;
}

void fromPatchPoint(const PatchPoint& patch, WindowKeyframe& host, ActivePoint& point) {
  point.host = &host;
  point.u = patch.u;
  point.v = patch.v;
  point.idepth = point.idepth_backup = patch.idepth;
  point.is_corner = patch.is_corner;
  point.fixed = true;
  for (int k = 0; k < kPatternSize; ++k) {
    point.colors[k] = patch.colors[k];
    point.grad_weights[k] = patch.grad_weights[k];
  }
}

bool initActivePoint(ActivePoint& point, WindowKeyframe& host, float u, float v, float idepth,
                     float gradient_weight_c) {
  const Level0View img = host.pyramid().level0();
  if (!isInsideForBilinear(u, v, img.width, img.height, static_cast<float>(kPatternPadding) + 1.f))
    return false;
  point.host = &host;
  point.u = u;
  point.v = v;
  point.idepth = point.idepth_backup = idepth;
  const float c2 = gradient_weight_c * gradient_weight_c;
  for (int k = 0; k < kPatternSize; ++k) {
    const GradientPixel g = interpolateBilinear(img, u + static_cast<float>(kPatternOffsets[k][0]),
                                                v + static_cast<float>(kPatternOffsets[k][1]));
    if (!std::isfinite(g.intensity)) return false;
    point.colors[k] = g.intensity;
    point.grad_weights[k] = std::sqrt(c2 / (c2 + g.dx * g.dx + g.dy * g.dy));
  }
  return true;
}

}  // namespace ldsm
