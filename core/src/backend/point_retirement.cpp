// Points leave the window when the newest keyframe no longer sees them (DSO's out-of-view
// rule): a point whose residual in the newest keyframe fell outside the image, or whose two
// newest residuals are both outliers, stops being optimised. Points measured often enough are
// marginalised into the prior (their information stays); the rest are dropped. Without this rule
// a forward-moving camera keeps far-behind keyframes alive through points it passed long ago,
// while new keyframes find no room for points of their own.
#include <algorithm>

#include "backend/mapper.h"

namespace ldsm {

namespace {

enum class PointFate { Keep, Marginalize, Drop };

const PointResidual* residualTo(const ActivePoint& p, const WindowKeyframe* target) {
  for (const auto& r : p.residuals)
    if (r.target == target) return &r;
  return nullptr;
}

}  // namespace

int Mapper::retireLostPoints() {
  const int n = static_cast<int>(window_.size());
  if (n < 2) return 0;
  const WindowKeyframe* newest = window_[n - 1].get();
  const WindowKeyframe* previous = window_[n - 2].get();
  constexpr int kMinInliersToMarginalize = 3;
  const auto fate = [&](const ActivePoint& p) {
    if (p.host == newest) return PointFate::Keep;
    const PointResidual* r_new = residualTo(p, newest);
    if (r_new == nullptr) return PointFate::Keep;
    bool lost = r_new->state == ResidualState::OutOfBounds;
    if (!lost && r_new->state == ResidualState::Outlier && p.host != previous) {
      const PointResidual* r_prev = residualTo(p, previous);
      lost = r_prev != nullptr && r_prev->state == ResidualState::Outlier;
    }
    if (!lost) return PointFate::Keep;
    return p.inlier_residuals >= kMinInliersToMarginalize && p.hessian_idepth > 0.f
               ? PointFate::Marginalize
               : PointFate::Drop;
  };
  std::vector<const ActivePoint*> to_prior;
  std::vector<HostedPoint> finished;
  for (auto& kf : window_)
    for (auto& p : kf->points)
      if (fate(*p) == PointFate::Marginalize) {
        recordCornerDepth(*p);
        kf->retired_points.push_back(toPatchPoint(*p));
        to_prior.push_back(p.get());
        finished.push_back({worldPoint(*p), p->host->id()});
      }
  optimizer_.marginalizePoints(windowView(), to_prior, prior_);
  int retired = 0;
  for (auto& kf : window_) {
    auto& pts = kf->points;
    const auto end = std::remove_if(pts.begin(), pts.end(),
                                    [&](const auto& p) { return fate(*p) != PointFate::Keep; });
    retired += static_cast<int>(pts.end() - end);
    pts.erase(end, pts.end());
  }
  update_.points.insert(update_.points.end(), finished.begin(), finished.end());
  return retired;
}

}  // namespace ldsm
