#include "map/map_depth.h"

#include <algorithm>
#include <cstddef>
#include <unordered_map>

namespace ldsm {
namespace {

template <typename T>
T median(std::vector<T>& values) {
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

}  // namespace

std::optional<double> medianHostDepth(const std::vector<PatchPoint>& points) {
  std::vector<float> depths;
  depths.reserve(points.size());
  for (const PatchPoint& p : points)
    if (p.idepth > 0.f) depths.push_back(1.f / p.idepth);
  if (depths.empty()) return std::nullopt;
  return static_cast<double>(median(depths));
}

std::optional<double> medianKeyframeDepth(const StoredMap& map) {
  std::unordered_map<int, double> scale;
  for (const KeyframeRecord& r : map.keyframes) scale[r.id] = r.scale;
  std::vector<double> depths;
  for (const std::shared_ptr<const MarginalizedKeyframe>& kf : map.data) {
    if (!kf) continue;
    const auto s = scale.find(kf->id);
    if (s == scale.end()) continue;
    if (const std::optional<double> d = medianHostDepth(kf->points))
      depths.push_back(s->second * *d);
  }
  if (depths.empty()) return std::nullopt;
  return median(depths);
}

}  // namespace ldsm
