#include "features/orb_matching.h"

#include <limits>

#include "model/popcount_dispatch.h"

namespace ldsm {
namespace {

/// Nearest and second nearest of `d` among `set` (indices and distances).
LDSM_POPCNT_CLONES
void nearest(const OrbDescriptor& d, const std::vector<OrbDescriptor>& set, int* best,
             int* best_dist, int* second_dist) {
  *best = -1;
  *best_dist = *second_dist = std::numeric_limits<int>::max();
  for (std::size_t j = 0; j < set.size(); ++j) {
    const int h = hammingDistance(d, set[j]);
    if (h < *best_dist) {
      *second_dist = *best_dist;
      *best_dist = h;
      *best = static_cast<int>(j);
    } else if (h < *second_dist) {
      *second_dist = h;
    }
  }
}

}  // namespace

std::vector<std::pair<int, int>> matchOrb(const std::vector<OrbDescriptor>& query,
                                          const std::vector<OrbDescriptor>& train,
                                          const OrbMatchSettings& settings) {
  if (query.empty() || train.empty()) return {};
  std::vector<int> train_best(settings.mutual ? train.size() : 0, -1);
  if (settings.mutual) {
    for (std::size_t j = 0; j < train.size(); ++j) {
      int b, bd, sd;
      nearest(train[j], query, &b, &bd, &sd);
      train_best[j] = b;
    }
  }
  std::vector<std::pair<int, int>> out(query.size());
  std::size_t count = 0;
  for (std::size_t i = 0; i < query.size(); ++i) {
    int b, bd, sd;
    nearest(query[i], train, &b, &bd, &sd);
    if (b < 0 || bd > settings.max_distance) continue;
    if (sd != std::numeric_limits<int>::max() &&
        !(static_cast<float>(bd) < settings.ratio * static_cast<float>(sd)))
      continue;
    if (settings.mutual && train_best[b] != static_cast<int>(i)) continue;
    out[count++] = {static_cast<int>(i), b};
  }
  out.resize(count);
  return out;
}

}  // namespace ldsm
