#include "backend/reference_budget.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace ldsm {

int referencePointBudget(double ratio, int active_points) {
  if (!(ratio > 0.0)) return 0;
  return static_cast<int>(std::max(1L, std::lround(ratio * active_points)));
}

void thinToReferenceBudget(std::vector<DepthPoint>& points, int budget) {
  if (budget <= 0 || points.size() <= static_cast<std::size_t>(budget)) return;
  const std::int64_t map_points =
      std::count_if(points.begin(), points.end(), [](const DepthPoint& p) { return p.from_map; });
  if (map_points == 0) return;
  const std::int64_t own = static_cast<std::int64_t>(points.size()) - map_points;
  if (own == 0) return;  // more map points than the budget: those alone
  const std::int64_t room = std::max<std::int64_t>(0, budget - map_points);
  std::int64_t i = 0;
  std::size_t kept = 0;
  for (const DepthPoint& p : points) {
    if (!p.from_map) {
      const bool keep = (i + 1) * room / own > i * room / own;
      ++i;
      if (!keep) continue;
    }
    points[kept++] = p;
  }
  points.resize(kept);
}

}  // namespace ldsm
