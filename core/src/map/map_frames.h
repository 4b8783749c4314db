// Which map each keyframe belongs to, and the frame poses are reported in. A new map starts when
// tracking was lost and relocalisation timed out; it lives in its own frame and scale until a loop
// connects it to an earlier map, when the two are merged (the earlier one is moved into the
// current one's frame, where the window is). The first map's frame stays the frame of every
// reported pose: reportFrame() maps the internal world frame into it, and a pose of a map not
// (yet) connected to the first one is reported in its own frame with its map number.
#pragma once

#include <vector>

#include "ldsm/types.h"
#include "math/se3.h"
#include "math/sim3.h"

namespace ldsm {

class MapFrames {
 public:
  /// The map new keyframes belong to.
  int current() const { return current_; }
  /// Starts a new map; returns its number.
  int startNew() {
    parent_.push_back(static_cast<int>(parent_.size()));
    current_ = static_cast<int>(parent_.size()) - 1;
    return current_;
  }
  /// The map `map` has been merged into, transitively (itself when never merged).
  int root(int map) const {
    if (map < 0 || map >= static_cast<int>(parent_.size())) return map;
    while (parent_[map] != map) map = parent_[map];
    return map;
  }
  /// Map `from` was moved into map `into`'s frame by S_into_from (internal coordinates of
  /// `from` -> those of `into`).
  void merge(int from, int into, const Sim3d& S_into_from) {
    const int a = root(from), b = root(into);
    if (a == b) return;
    if (a == root(0)) S_report_world_ = S_report_world_ * S_into_from.inverse();
    parent_[a] = b;
  }
  /// The label of a pose of map `map` as reported (StampedPose::map): 0 when connected to the
  /// first map, else the root of its own map.
  int label(int map) const {
    const int r = root(map);
    return r == root(0) ? 0 : r;
  }
  /// Internal world -> reported frame, for poses whose label is 0.
  const Sim3d& reportFrame() const { return S_report_world_; }
  /// A camera pose (camera-to-world, internal frame) of a label-0 map as reported.
  Pose report(const SE3d& T_w_c) const {
    Pose p;
    p.rotation = (S_report_world_.so3() * T_w_c.so3()).quaternion();
    p.translation = S_report_world_ * T_w_c.translation();
    return p;
  }

 private:
  std::vector<int> parent_{0};
  int current_ = 0;
  Sim3d S_report_world_;
};

}  // namespace ldsm
