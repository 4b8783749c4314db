#include "map/spatial_index.h"

#include <algorithm>
#include <cmath>

namespace ldsm {

SpatialIndex::Key SpatialIndex::key(std::int64_t x, std::int64_t y, std::int64_t z) const {
  // 21 bits per axis (cells wrap far beyond any map; a wrapped cell only adds candidates that
  // the distance test then rejects).
  constexpr std::int64_t kMask = (1 << 21) - 1;
  return ((x & kMask) << 42) | ((y & kMask) << 21) | (z & kMask);
}

SpatialIndex::Key SpatialIndex::key(const Eigen::Vector3d& p) const {
  return key(static_cast<std::int64_t>(std::floor(p.x() / cell_)),
             static_cast<std::int64_t>(std::floor(p.y() / cell_)),
             static_cast<std::int64_t>(std::floor(p.z() / cell_)));
}

void SpatialIndex::set(int id, const Eigen::Vector3d& centre) {
  if (!centre.allFinite()) return;
  remove(id);
  const Key k = key(centre);
  cells_[k].push_back(id);
  where_[id] = {k, centre};
}

void SpatialIndex::remove(int id) {
  const auto it = where_.find(id);
  if (it == where_.end()) return;
  auto& cell = cells_[it->second.first];
  cell.erase(std::remove(cell.begin(), cell.end(), id), cell.end());
  if (cell.empty()) cells_.erase(it->second.first);
  where_.erase(it);
}

std::vector<int> SpatialIndex::near(const Eigen::Vector3d& centre, double radius) const {
  std::vector<int> out;
  if (!centre.allFinite() || !(radius > 0.0)) return out;
  const double r2 = radius * radius;
  const auto lo = [&](double v) { return std::floor((v - radius) / cell_); };
  const auto hi = [&](double v) { return std::floor((v + radius) / cell_); };
  // A search box of more cells than the index holds (a large radius): every keyframe is tested
  // instead of visiting the box's cells. (The box was once capped at 16 cells per axis from its
  // low corner, which dropped the keyframes at the centre for radii above 8 cells.)
  const double box_cells = (hi(centre.x()) - lo(centre.x()) + 1.0) *
                           (hi(centre.y()) - lo(centre.y()) + 1.0) *
                           (hi(centre.z()) - lo(centre.z()) + 1.0);
  if (!(box_cells <= static_cast<double>(cells_.size()))) {
    for (const auto& [id, where] : where_)
      if ((where.second - centre).squaredNorm() <= r2) out.push_back(id);
    std::sort(out.begin(), out.end());
    return out;
  }
  const auto x0 = static_cast<std::int64_t>(lo(centre.x()));
  const auto x1 = static_cast<std::int64_t>(hi(centre.x()));
  const auto y0 = static_cast<std::int64_t>(lo(centre.y()));
  const auto y1 = static_cast<std::int64_t>(hi(centre.y()));
  const auto z0 = static_cast<std::int64_t>(lo(centre.z()));
  const auto z1 = static_cast<std::int64_t>(hi(centre.z()));
  for (std::int64_t x = x0; x <= x1; ++x)
    for (std::int64_t y = y0; y <= y1; ++y)
      for (std::int64_t z = z0; z <= z1; ++z) {
        const auto it = cells_.find(key(x, y, z));
        if (it == cells_.end()) continue;
        for (const int id : it->second) {
          const auto w = where_.find(id);
          if ((w->second.second - centre).squaredNorm() <= r2 &&
              std::find(out.begin(), out.end(), id) == out.end())
            out.push_back(id);
        }
      }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace ldsm
