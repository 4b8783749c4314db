// Relative pose error over fixed path lengths, as in the KITTI odometry benchmark (Geiger et al.
// 2012): for every start pose and every segment length L, the relative motion of the estimate
// over the first stretch of ground truth at least L long is compared with the true relative
// motion. No alignment is applied (relative motions do not depend on the world frame), except an
// optional global scale for monocular estimates.
#pragma once

#include <cstddef>
#include <vector>

#include "ldsm/types.h"

namespace ldsm::eval {

struct RpeOptions {
  /// Segment lengths in ground-truth units (m). Empty: defaultRpeLengths(path length).
  std::vector<double> lengths;
  /// Start a segment at every `step`-th matched pose (KITTI uses 10 at 10 Hz).
  std::size_t step = 1;
  /// Factor applied to the estimated translations first (e.g. the Sim(3) scale of the ATE
  /// alignment for a monocular estimate); 1 = evaluate the estimate as it is.
  double scale = 1.0;
  /// Timestamp tolerance of the association [s].
  double max_dt = 0.02;
};

/// Errors of the segments of one length.
struct RpeLengthStats {
  double length = 0.0;               ///< segment length [m]
  std::size_t segments = 0;          ///< segments of this length that fit in the trajectory
  double translation_percent = 0.0;  ///< mean ||translation error|| / length * 100
  double rotation_deg_per_m = 0.0;   ///< mean rotation error angle / length [deg/m]
};

struct RpeResult {
  std::vector<RpeLengthStats> per_length;  ///< one entry per requested length
  std::size_t segments = 0;                ///< all segments; 0 when the path is too short
  double translation_percent = 0.0;        ///< mean over all segments (KITTI's headline figure)
  double rotation_deg_per_m = 0.0;         ///< mean over all segments [deg/m]
  bool valid() const { return segments > 0; }
};

/// KITTI's lengths 100, 200, ..., 800 m for paths of at least 800 m; otherwise 10 %, 20 %, ...,
/// 80 % of the path length. Empty for a path of zero length.
std::vector<double> defaultRpeLengths(double path_length);

/// Relative pose error of `est` against `gt` (poses matched by timestamp, see associate()).
/// Throws ldsm::ConfigError for a non-positive length, step 0 or a non-positive scale.
RpeResult computeRpe(const Trajectory& gt, const Trajectory& est, const RpeOptions& options = {});

}  // namespace ldsm::eval
