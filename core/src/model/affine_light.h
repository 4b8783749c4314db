// Affine brightness transfer between two frames (DSO's photometric model):
//   I_t[p'] ~ scale * I_h[p] + offset,  scale = (t_t e^{a_t}) / (t_h e^{a_h}),
//   offset = b_t - scale * b_h,
// where t is the exposure time (1 when unknown) and (a, b) the per-frame affine parameters.
#pragma once

#include <Eigen/Core>
#include <cmath>

namespace ldsm {

struct AffineLight {
  double a = 0.0;
  double b = 0.0;
};

/// (scale, offset) mapping host intensities into the target frame.
inline Eigen::Vector2d affineTransfer(double exposure_host, double exposure_target,
                                      const AffineLight& host, const AffineLight& target) {
  const double scale = std::exp(target.a - host.a) * exposure_target / exposure_host;
  return {scale, target.b - scale * host.b};
}

}  // namespace ldsm
