// Absolute trajectory error (ATE): position error after aligning the estimate to ground truth.
#pragma once

#include <cstddef>
#include <vector>

#include "ldsm/eval/alignment.h"
#include "ldsm/eval/association.h"
#include "ldsm/types.h"

namespace ldsm::eval {

/// Which transform aligns the estimate to ground truth before the ATE is measured.
enum class AlignMode {
  Sim3,  ///< rotation, translation and scale (monocular: scale is unobservable)
  SE3,   ///< rotation and translation only: a wrong scale shows up as error
};

struct AteResult {
  double rmse = 0.0;               ///< root mean square position error [gt units, m]
  double mean = 0.0;               ///< mean position error
  double median = 0.0;             ///< median position error
  double max = 0.0;                ///< largest position error
  double rotation_rmse_deg = 0.0;  ///< RMS orientation error after alignment [deg]
  std::size_t matched = 0;         ///< number of matched (evaluated) poses
  double gt_path_length = 0.0;     ///< path length of the matched ground-truth poses
  Alignment alignment;             ///< est -> gt transform that was applied
  /// Scale of the best Sim(3) alignment, computed in both modes: in SE3 mode it tells the scale
  /// error of the estimate (1 = correct metric scale; est scaled by k gives 1/k).
  double sim3_scale = 1.0;
  std::vector<IndexPair> pairs;  ///< the matched poses
  std::vector<double> errors;    ///< position error of each pair
  Trajectory aligned_estimate;   ///< every estimated pose mapped by `alignment`
};

/// Matches poses by timestamp (within max_dt seconds, see associate()), aligns the matched
/// estimated positions to the ground-truth ones (Umeyama, Sim(3) or SE(3)) and measures the
/// position differences. Throws ldsm::InputError when fewer than 3 poses match or the matched
/// positions are degenerate (see alignUmeyama()).
AteResult computeAte(const Trajectory& gt, const Trajectory& est, AlignMode mode = AlignMode::Sim3,
                     double max_dt = 0.02);

/// The ATE of `est` under a given alignment (est -> gt) instead of its own: for an estimate that
/// must be in the same frame as another, e.g. a session started in a saved map, measured under the
/// Sim(3) that aligns the session that made the map (docs/map-sessions.md). `sim3_scale` is the
/// given alignment's scale. Throws ldsm::InputError when fewer than 3 poses match.
AteResult computeAteUnder(const Trajectory& gt, const Trajectory& est, const Alignment& alignment,
                          double max_dt = 0.02);

}  // namespace ldsm::eval
