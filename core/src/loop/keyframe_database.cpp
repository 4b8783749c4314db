#include "loop/keyframe_database.h"

#include <algorithm>
#include <string>
#include <utility>

#include "ldsm/error.h"

namespace ldsm::loop {

void KeyframeDatabase::add(int keyframe_id, const BowVector& bow, FeatureVector features) {
  for (std::size_t i = 1; i < bow.size(); ++i) {
    if (!(bow[i - 1].first < bow[i].first)) {
      throw InputError("KeyframeDatabase: the BoW vector of keyframe " +
                       std::to_string(keyframe_id) + " is not sorted by word");
    }
  }
  remove(keyframe_id);
  std::uint32_t slot = 0;
  if (!free_slots_.empty()) {
    slot = free_slots_.back();
    free_slots_.pop_back();
  } else {
    slot = static_cast<std::uint32_t>(entries_.size());
    entries_.emplace_back();
  }
  Entry& e = entries_[slot];
  e.keyframe_id = keyframe_id;
  e.bow = bow;
  e.features = std::move(features);
  slot_of_[keyframe_id] = slot;
  for (const auto& [word, weight] : bow) {
    if (word >= inverted_.size()) inverted_.resize(static_cast<std::size_t>(word) + 1);
    inverted_[word].push_back(Posting{slot, weight});
  }
}

bool KeyframeDatabase::remove(int keyframe_id) {
  const auto it = slot_of_.find(keyframe_id);
  if (it == slot_of_.end()) return false;
  const std::uint32_t slot = it->second;
  Entry& e = entries_[slot];
  for (const auto& entry : e.bow) {
    auto& postings = inverted_[entry.first];
    postings.erase(std::remove_if(postings.begin(), postings.end(),
                                  [slot](const Posting& p) { return p.slot == slot; }),
                   postings.end());
  }
  e = Entry();
  free_slots_.push_back(slot);
  slot_of_.erase(it);
  return true;
}

void KeyframeDatabase::clear() {
  inverted_.clear();
  entries_.clear();
  free_slots_.clear();
  slot_of_.clear();
}

const BowVector* KeyframeDatabase::bow(int keyframe_id) const {
  const auto it = slot_of_.find(keyframe_id);
  return it == slot_of_.end() ? nullptr : &entries_[it->second].bow;
}

const FeatureVector* KeyframeDatabase::featureVector(int keyframe_id) const {
  const auto it = slot_of_.find(keyframe_id);
  return it == slot_of_.end() ? nullptr : &entries_[it->second].features;
}

std::vector<PlaceCandidate> KeyframeDatabase::query(const BowVector& bow,
                                                    const std::function<bool(int)>& exclude,
                                                    int max_results, float min_score) const {
  // For L1-normalised positive vectors, 1 - 0.5 |a - b|_1 = sum over shared words of min(a, b).
  std::vector<float> score(entries_.size(), 0.f);
  std::vector<char> seen(entries_.size(), 0);
  std::vector<std::uint32_t> touched;
  for (const auto& [word, weight] : bow) {
    if (word >= inverted_.size()) continue;
    for (const Posting& p : inverted_[word]) {
      if (!seen[p.slot]) {
        seen[p.slot] = 1;
        touched.push_back(p.slot);
      }
      score[p.slot] += std::min(weight, p.weight);
    }
  }
  std::vector<PlaceCandidate> out;
  out.reserve(touched.size());
  for (std::uint32_t slot : touched) {
    const int id = entries_[slot].keyframe_id;
    const float s = std::min(score[slot], 1.f);
    if (s < min_score || s <= 0.f) continue;
    if (exclude && exclude(id)) continue;
    out.push_back(PlaceCandidate{id, s});
  }
  auto better = [](const PlaceCandidate& a, const PlaceCandidate& b) {
    return a.score > b.score || (a.score == b.score && a.keyframe_id < b.keyframe_id);
  };
  if (max_results > 0 && out.size() > static_cast<std::size_t>(max_results)) {
    std::partial_sort(out.begin(), out.begin() + max_results, out.end(), better);
    out.resize(static_cast<std::size_t>(max_results));
  } else {
    std::sort(out.begin(), out.end(), better);
  }
  return out;
}

std::vector<int> KeyframeDatabase::keyframeIds() const {
  std::vector<int> ids;
  ids.reserve(slot_of_.size());
  for (const auto& [id, slot] : slot_of_) ids.push_back(id);
  std::sort(ids.begin(), ids.end());
  return ids;
}

}  // namespace ldsm::loop
