// Keyframe database for place recognition: an inverted index (word -> keyframes holding it, with
// their BoW weights) that scores a query against every keyframe sharing at least one word, and a
// direct index (keyframe -> its FeatureVector) for guided descriptor matching.
//
// Scores are DBoW's L1 score (bowScore(): 1 identical, 0 no shared word), accumulated over the
// query's words only, so a query costs the total length of the posting lists of its words.
// The database does not know the vocabulary; all BoW vectors must come from the same one
// (rebuild it with clear() + add() when the vocabulary changes).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <unordered_map>
#include <vector>

#include "loop/loop_types.h"

namespace ldsm::loop {

/// One query result.
struct PlaceCandidate {
  int keyframe_id = -1;
  float score = 0.f;  ///< bowScore(query, keyframe) in [0, 1]
};

class KeyframeDatabase {
 public:
  /// Adds (or replaces) a keyframe. The BoW vector must be sorted by word (as
  /// Vocabulary::transform() returns it); throws InputError otherwise.
  void add(int keyframe_id, const BowVector& bow, FeatureVector features = {});
  /// Removes a keyframe; returns false when it is not in the database.
  bool remove(int keyframe_id);
  void clear();

  std::size_t size() const { return slot_of_.size(); }
  bool contains(int keyframe_id) const { return slot_of_.count(keyframe_id) != 0; }
  /// The stored BoW vector / FeatureVector of a keyframe, nullptr when absent.
  const BowVector* bow(int keyframe_id) const;
  const FeatureVector* featureVector(int keyframe_id) const;

  /// Keyframes that share a word with `bow`, best first (ties: lower id first), at most
  /// `max_results` (all when <= 0), leaving out those for which `exclude(id)` is true and those
  /// scoring below `min_score`.
  std::vector<PlaceCandidate> query(const BowVector& bow,
                                    const std::function<bool(int)>& exclude = {},
                                    int max_results = 0, float min_score = 0.f) const;

  /// Ids of all stored keyframes, increasing.
  std::vector<int> keyframeIds() const;

 private:
  struct Posting {
    std::uint32_t slot;
    float weight;
  };
  struct Entry {
    int keyframe_id = -1;
    BowVector bow;
    FeatureVector features;
  };

  std::vector<std::vector<Posting>> inverted_;  ///< indexed by WordId
  std::vector<Entry> entries_;                  ///< by slot; keyframe_id -1 when free
  std::vector<std::uint32_t> free_slots_;
  std::unordered_map<int, std::uint32_t> slot_of_;
};

}  // namespace ldsm::loop
