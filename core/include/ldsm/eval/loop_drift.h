// Accumulated drift of a loop trajectory, following the TUM monoVO benchmark (Engel, Usenko,
// Cremers: "A Photometrically Calibrated Benchmark For Monocular Visual Odometry", 2016, Sec. 4).
//
// The sequence starts and ends at the same place and ground truth is known for a start segment S
// and an end segment E. With p_i the estimated positions of all n frames and p^_i the ground
// truth, the estimate is aligned to each segment separately with Sim(3):
//   S_s = argmin_{S in Sim(3)} sum_{i in S} ||S p_i - p^_i||^2
//   S_e = argmin_{S in Sim(3)} sum_{i in E} ||S p_i - p^_i||^2
// The accumulated drift is the similarity S_e * S_s^-1 (a map from the ground-truth frame to
// itself: undo the start alignment, apply the end alignment). Its translation norm is the
// translational drift e_t (ground-truth units), its rotation angle the rotational drift e_r and
// its scale the scale drift e_s (1 = none; the paper quotes e_s as a factor > 1, i.e.
// max(e_s, 1/e_s)). Because these three depend on each other and on where the world origin lies,
// the paper proposes the alignment error
//   e_align = sqrt( 1/n sum_{i=1..n} ||S_s p_i - S_e p_i||^2 ),
// the RMS distance between the trajectory as placed by the start alignment and as placed by the
// end alignment, summed over all n tracked frames (equivalently, over the whole estimate). For
// trajectories where ground truth exists only at the segments it is also informative to restrict
// the sum to the frames of both segments: we report that as e_align_segments.
#pragma once

#include <cstddef>
#include <vector>

#include "ldsm/eval/alignment.h"
#include "ldsm/eval/association.h"
#include "ldsm/types.h"

namespace ldsm::eval {

struct LoopDriftResult {
  Alignment start_alignment;              ///< S_s: est -> gt, fitted on the start segment
  Alignment end_alignment;                ///< S_e: est -> gt, fitted on the end segment
  Alignment drift;                        ///< S_e * S_s^-1
  double translation_drift = 0.0;         ///< e_t = ||translation of the drift|| [gt units]
  double rotation_drift_deg = 0.0;        ///< e_r = rotation angle of the drift [deg]
  double scale_drift = 1.0;               ///< e_s = scale of the drift (1 = no scale drift)
  double alignment_error = 0.0;           ///< e_align over every estimated pose [gt units]
  double alignment_error_segments = 0.0;  ///< e_align over the poses of both segments
  std::size_t start_poses = 0;            ///< matched poses in the start segment
  std::size_t end_poses = 0;              ///< matched poses in the end segment
};

/// Drift from explicitly given segments (pairs of matched gt/est indices). Every estimated pose
/// enters e_align. Throws ldsm::InputError when a segment is degenerate (see alignUmeyama()).
LoopDriftResult computeLoopDrift(const Trajectory& gt, const Trajectory& est,
                                 const std::vector<IndexPair>& start_segment,
                                 const std::vector<IndexPair>& end_segment);

/// Options of the convenience overload that picks the segments itself.
struct LoopDriftOptions {
  /// Matched poses per segment: the first and the last `segment_poses` matched poses. 0 = auto:
  /// a fifth of the matched poses (at least 3).
  std::size_t segment_poses = 0;
  double max_dt = 0.02;  ///< timestamp tolerance of the association [s]
};

/// Associates the poses by timestamp and uses the first and last `segment_poses` matches as start
/// and end segment. Throws ldsm::InputError when the matches cannot hold two disjoint segments of
/// at least 3 poses.
LoopDriftResult computeLoopDrift(const Trajectory& gt, const Trajectory& est,
                                 const LoopDriftOptions& options = {});

}  // namespace ldsm::eval
