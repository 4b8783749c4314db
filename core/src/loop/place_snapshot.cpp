#include "loop/place_snapshot.h"

#include <algorithm>

namespace ldsm::loop {

std::vector<PlaceCandidate> PlaceSnapshot::query(const std::vector<OrbDescriptor>& descriptors,
                                                 int max_results, float min_score) const {
  std::vector<PlaceCandidate> out;
  if (!vocabulary || descriptors.empty() || max_results <= 0) return out;
  BowVector bow;
  vocabulary->transform(descriptors, bow);
  for (const auto& [id, kf] : keyframes) {
    const float score = bowScore(bow, *kf);
    if (score > 0.f && score >= min_score) out.push_back({id, score});
  }
  const auto better = [](const PlaceCandidate& a, const PlaceCandidate& b) {
    return a.score != b.score ? a.score > b.score : a.keyframe_id < b.keyframe_id;
  };
  const std::size_t n = std::min(out.size(), static_cast<std::size_t>(max_results));
  std::partial_sort(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(n), out.end(), better);
  out.resize(n);
  return out;
}

}  // namespace ldsm::loop
