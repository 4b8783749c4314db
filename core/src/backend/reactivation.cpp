// Map reuse inside the window (docs/map-reuse.md): map keyframes brought back as fixed hosts of
// their points, how well they fit the newest keyframe, and taking them out again.
#include <algorithm>

#include "backend/mapper.h"

namespace ldsm {

void Mapper::reactivate(const MarginalizedKeyframe& keyframe, const SE3d& T_w_c, double scale) {
  deactivate(keyframe.id);
  auto kf = std::make_unique<WindowKeyframe>(keyframe.id, keyframe.frame_index, keyframe.timestamp,
                                             keyframe.exposure, nullptr);
  kf->setInitialState(T_w_c.inverse(), keyframe.aff);
  kf->is_reactivated = true;
  const float inv_scale = static_cast<float>(1.0 / scale);
  kf->points.reserve(keyframe.points.size());
  for (const PatchPoint& pp : keyframe.points) {
    auto p = std::make_unique<ActivePoint>();
    fromPatchPoint(pp, *kf, *p);
    p->idepth = p->idepth_backup = pp.idepth * inv_scale;
    p->id = next_point_id_++;
    p->residuals.reserve(window_.size());
    for (const auto& target : window_) p->residuals.push_back({target.get()});
    kf->points.push_back(std::move(p));
  }
  kf->points_created = static_cast<int>(kf->points.size());
  reactivated_.push_back(std::move(kf));
}

void Mapper::deactivate(int keyframe_id) {
  reactivated_fit_.erase(
      std::remove_if(reactivated_fit_.begin(), reactivated_fit_.end(),
                     [&](const ReactivatedFit& f) { return f.id == keyframe_id; }),
      reactivated_fit_.end());
  reactivated_.erase(std::remove_if(reactivated_.begin(), reactivated_.end(),
                                    [&](const std::unique_ptr<WindowKeyframe>& k) {
                                      return k->id() == keyframe_id;
                                    }),
                     reactivated_.end());
}

void Mapper::deactivateAll() {
  reactivated_fit_.clear();
  reactivated_.clear();
}

std::vector<int> Mapper::reactivatedIds() const {
  std::vector<int> ids;
  for (const auto& kf : reactivated_) ids.push_back(kf->id());
  return ids;
}

std::vector<Mapper::ReactivatedFit> Mapper::measureReactivatedFit() const {
  std::vector<ReactivatedFit> out;
  if (window_.empty()) return out;
  const WindowKeyframe* newest = window_.back().get();
  for (const auto& kf : reactivated_) {
    ReactivatedFit f;
    f.id = kf->id();
    for (const auto& p : kf->points)
      for (const PointResidual& r : p->residuals)
        if (r.target == newest && r.state != ResidualState::OutOfBounds) {
          ++f.residuals;
          f.inliers += r.state == ResidualState::Inlier ? 1 : 0;
        }
    out.push_back(f);
  }
  return out;
}

}  // namespace ldsm
