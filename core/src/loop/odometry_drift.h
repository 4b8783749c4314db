// The odometry's drift model, for the pose graph and for deciding whether a loop shows drift.
// The window's relative poses are accurate, but errors accumulate along the chain of keyframes: a
// random walk per keyframe step in rotation (rotation_drift, radians) and log scale
// (scale_drift), and a translation error proportional to the distance travelled
// (translation_drift). Covariances are in the Sim(3) tangent order [rho, phi, sigma] of sim3.h.
#pragma once

#include "ldsm/config.h"
#include "loop/sim3_edge.h"
#include "math/sim3.h"

namespace ldsm::loop {

struct OdometryDriftModel {
  double rotation = 5e-4;
  double scale = 2e-3;
  double translation = 0.01;
  /// Floor of the distance per step (map units), so that a pure rotation keeps a finite
  /// translation uncertainty.
  double min_step = 1e-3;

  static OdometryDriftModel fromConfig(const LoopConfig& c) {
    return {c.odometry_rotation_drift, c.odometry_scale_drift, c.odometry_translation_drift};
  }

  /// Information of one odometry edge with relative motion S_prev_cur.
  Matrix7d edgeInformation(const Sim3d& S_prev_cur) const;

  /// Covariance of the relative pose between two keyframes `steps` keyframes and `path_length`
  /// map units apart along the chain, whose relative pose is S_rel: the random walks, the
  /// translation drift, and the rotation and scale drift acting on the lever arm |t_rel|.
  Matrix7d chainCovariance(int steps, double path_length, const Sim3d& S_rel) const;
};

/// The a-posteriori scale lambda >= 1 of a chain covariance such that the loop's disagreement d
/// (tangent, 7 DoF) has its expected squared Mahalanobis distance under loop_cov + lambda *
/// chain_cov: d^T (loop_cov + lambda chain_cov)^-1 d = 7. 1 when d is already within that.
double driftScaleFor(const Vector7d& d, const Matrix7d& loop_cov, const Matrix7d& chain_cov);

}  // namespace ldsm::loop
