// The tracking reference's budget (reuse.reference_point_ratio; docs/map-reuse.md, "The tracking
// reference's budget"): map keyframes brought back into the window add their points to the
// reference every frame is tracked against. With a budget, the map keyframes' points all stay
// (they hold a revisit on the map) and the window's own points are thinned evenly to fill what is
// left.
#pragma once

#include <vector>

#include "model/depth_point.h"

namespace ldsm {

/// The budget for `ratio` times `active_points` (window.active_points): 0, no limit, for a ratio
/// of 0; otherwise at least 1.
int referencePointBudget(double ratio, int active_points);

/// Thins `points` to `budget` (> 0) when there are more and some are map keyframes' points
/// (DepthPoint::from_map): every map point stays, in order, and of the window's own points
/// max(0, budget - map points) stay, evenly spread in their order (own point i is kept when
/// floor((i + 1) room / own) > floor(i room / own)). Points without a map point among them, or
/// within the budget, or a budget of 0, are left as they are.
void thinToReferenceBudget(std::vector<DepthPoint>& points, int budget);

}  // namespace ldsm
