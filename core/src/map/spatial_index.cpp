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
  const auto lo = [&](double v) {
    return static_cast<std::int64_t>(std::floor((v - radius) / cell_));
  };
  const auto hi = [&](double v) {
    return static_cast<std::int64_t>(std::floor((v + radius) / cell_));
  };
  // Very large radii would visit too many cells: cap the span.
  constexpr std::int64_t kMaxSpan = 16;
  const std::int64_t x0 = lo(centre.x()), x1 = std::min(hi(centre.x()), x0 + kMaxSpan);
  const std::int64_t y0 = lo(centre.y()), y1 = std::min(hi(centre.y()), y0 + kMaxSpan);
  const std::int64_t z0 = lo(centre.z()), z1 = std::min(hi(centre.z()), z0 + kMaxSpan);
  const double r2 = radius * radius;
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
