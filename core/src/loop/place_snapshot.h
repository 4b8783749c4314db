// What relocalisation needs of place recognition, as an immutable value the loop closer publishes
// after every keyframe it indexed: the current vocabulary and every indexed keyframe's BoW vector
// (shared, never copied). Any thread may query it while the loop closer goes on: a kidnapped or
// freshly started camera is looked for in the whole map, not only near its last pose.
#pragma once

#include <memory>
#include <utility>
#include <vector>

#include "loop/keyframe_database.h"
#include "loop/vocabulary.h"
#include "model/orb_descriptor.h"

namespace ldsm::loop {

struct PlaceSnapshot {
  std::shared_ptr<const Vocabulary> vocabulary;  ///< null before the first (online) training
  /// (keyframe id, its BoW vector under `vocabulary`), by increasing id.
  std::vector<std::pair<int, std::shared_ptr<const BowVector>>> keyframes;

  /// The keyframes that look most like a view with these descriptors, best first (ties: lower id
  /// first), at most `max_results`, scoring at least `min_score` (bowScore). Empty without a
  /// vocabulary.
  std::vector<PlaceCandidate> query(const std::vector<OrbDescriptor>& descriptors, int max_results,
                                    float min_score = 0.f) const;
};

}  // namespace ldsm::loop
