// Which map keyframes the reuse search leaves alone for a while. A map keyframe taken out of the
// window (it no longer fitted the newest keyframe, or a better one replaced it) may come back in
// the search that took it out: one that fits about as well as the threshold is often right, and
// the search aligns it afresh. Taken out a second time within `rest_keyframes` keyframes, it
// rests for as many keyframes, so that it cannot come and go with every keyframe. A candidate
// the trial optimisation turned down rests at once (for its own period).
#pragma once

#include <utility>
#include <vector>

namespace ldsm {

class RestingKeyframes {
 public:
  explicit RestingKeyframes(int rest_keyframes = 5) : rest_keyframes_(rest_keyframes) {}

  /// Map keyframe `id` was taken out of the window when `newest_id` was the newest keyframe
  /// (keyframe ids grow by one per keyframe). Returns whether it now rests.
  bool takenOut(int id, int newest_id);
  /// `id` is not searched for the next `keyframes` keyframes after `newest_id`.
  void rest(int id, int newest_id, int keyframes);
  /// The keyframes that rest while `newest_id` is the newest (forgets those whose rest is over).
  std::vector<int> resting(int newest_id);

 private:
  int rest_keyframes_;
  std::vector<std::pair<int, int>> resting_;    ///< (id, last keyframe id of its rest)
  std::vector<std::pair<int, int>> taken_out_;  ///< (id, newest keyframe id when taken out)
};

}  // namespace ldsm
