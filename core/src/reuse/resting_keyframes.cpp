#include "reuse/resting_keyframes.h"

#include <algorithm>

namespace ldsm {

bool RestingKeyframes::takenOut(int id, int newest_id) {
  if (rest_keyframes_ <= 0) return false;
  taken_out_.erase(std::remove_if(taken_out_.begin(), taken_out_.end(),
                                  [&](const std::pair<int, int>& t) {
                                    return t.second + rest_keyframes_ < newest_id;
                                  }),
                   taken_out_.end());
  const auto before = std::find_if(taken_out_.begin(), taken_out_.end(),
                                   [&](const std::pair<int, int>& t) { return t.first == id; });
  if (before == taken_out_.end()) {
    taken_out_.push_back({id, newest_id});
    return false;
  }
  // After its rest it starts afresh: one more take-out is free.
  taken_out_.erase(before);
  rest(id, newest_id, rest_keyframes_);
  return true;
}

void RestingKeyframes::rest(int id, int newest_id, int keyframes) {
  if (keyframes <= 0) return;
  resting_.push_back({id, newest_id + keyframes});
}

std::vector<int> RestingKeyframes::resting(int newest_id) {
  resting_.erase(std::remove_if(resting_.begin(), resting_.end(),
                                [&](const std::pair<int, int>& r) { return r.second < newest_id; }),
                 resting_.end());
  std::vector<int> ids;
  ids.reserve(resting_.size());
  for (const auto& r : resting_) ids.push_back(r.first);
  return ids;
}

}  // namespace ldsm
