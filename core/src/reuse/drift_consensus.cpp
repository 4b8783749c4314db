#include "reuse/drift_consensus.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ldsm {

double poseDistancePx(const SE3d& a_c_w, const SE3d& b_c_w, const LevelCamera& camera,
                      const std::vector<Eigen::Vector3d>& scene_w) {
  double sum = 0.0;
  int n = 0;
  for (const Eigen::Vector3d& X : scene_w) {
    const Eigen::Vector3d a = a_c_w * X, b = b_c_w * X;
    if (!(a.z() > 1e-9) || !(b.z() > 1e-9)) continue;
    sum += (camera.project(a.cast<float>()) - camera.project(b.cast<float>())).norm();
    ++n;
  }
  return n > 0 ? sum / n : std::numeric_limits<double>::infinity();
}

DriftConsensus findDriftConsensus(const std::vector<DriftCandidate>& candidates,
                                  const LevelCamera& camera,
                                  const std::vector<Eigen::Vector3d>& scene_w, double agreement_px,
                                  int min_agreeing) {
  DriftConsensus best;
  if (min_agreeing <= 0) return best;
  int best_in_view = -1, best_id = -1;
  for (const DriftCandidate& c : candidates) {
    DriftConsensus s;
    s.id = c.id;
    s.T_c_w = c.T_c_w;
    for (const DriftCandidate& o : candidates) {
      const double px = poseDistancePx(c.T_c_w, o.T_c_w, camera, scene_w);
      if (px > agreement_px) continue;
      s.agreeing.push_back(o.id);
      s.spread_px = std::max(s.spread_px, px);
    }
    const std::size_t n = s.agreeing.size();
    const bool better =
        n > best.agreeing.size() ||
        (n == best.agreeing.size() &&
         (c.in_view > best_in_view || (c.in_view == best_in_view && c.id < best_id)));
    if (!better) continue;
    best = std::move(s);
    best_in_view = c.in_view;
    best_id = c.id;
  }
  best.found = static_cast<int>(best.agreeing.size()) >= min_agreeing;
  return best;
}

}  // namespace ldsm
