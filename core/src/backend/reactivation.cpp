// Map reuse inside the window (docs/map-reuse.md): map keyframes brought back as fixed hosts of
// their points, how well they fit the newest keyframe, and taking them out again.
#include <algorithm>
#include <cmath>
#include <iterator>

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
  const std::size_t before = reactivated_.size();
  reactivated_.erase(std::remove_if(reactivated_.begin(), reactivated_.end(),
                                    [&](const std::unique_ptr<WindowKeyframe>& k) {
                                      return k->id() == keyframe_id;
                                    }),
                     reactivated_.end());
  if (reactivated_.size() != before) wakeDormantPoints();
}

void Mapper::wakeDormantPoints() {
  for (auto& kf : window_) {
    if (kf->dormant.empty()) continue;
    kf->immature.insert(kf->immature.end(), std::make_move_iterator(kf->dormant.begin()),
                        std::make_move_iterator(kf->dormant.end()));
    kf->dormant.clear();
  }
}

bool Mapper::moveReactivated(int keyframe_id, const SE3d& T_w_c, double scale_ratio) {
  for (auto& kf : reactivated_) {
    if (kf->id() != keyframe_id) continue;
    kf->setInitialState(T_w_c.inverse(), kf->aff);
    const float inv_ratio = static_cast<float>(1.0 / scale_ratio);
    for (auto& p : kf->points) p->idepth = p->idepth_backup = p->idepth * inv_ratio;
    return true;
  }
  return false;
}

void Mapper::deactivateAll() {
  reactivated_fit_.clear();
  reactivated_.clear();
  wakeDormantPoints();
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

namespace {

/// Everything a window optimisation changes, to be put back.
struct WindowState {
  struct Frame {
    WindowKeyframe* kf;
    SE3d T_c_w;  // (the optimiser's step backups are its own, set before every step)
    AffineLight aff;
  };
  struct Point {
    ActivePoint* p;
    float idepth, idepth_backup, hessian_idepth, gradient_idepth;
    int inlier_residuals;
    bool verified;
    std::vector<PointResidual> residuals;
  };
  std::vector<Frame> frames;
  std::vector<Point> points;

  void add(WindowKeyframe& kf) {
    frames.push_back({&kf, kf.T_c_w, kf.aff});
    for (const auto& p : kf.points)
      points.push_back({p.get(), p->idepth, p->idepth_backup, p->hessian_idepth, p->gradient_idepth,
                        p->inlier_residuals, p->verified, p->residuals});
  }
  void restore() const {
    for (const Frame& f : frames) {
      f.kf->T_c_w = f.T_c_w;
      f.kf->aff = f.aff;
    }
    for (const Point& q : points) {
      q.p->idepth = q.idepth;
      q.p->idepth_backup = q.idepth_backup;
      q.p->hessian_idepth = q.hessian_idepth;
      q.p->gradient_idepth = q.gradient_idepth;
      q.p->inlier_residuals = q.inlier_residuals;
      q.p->verified = q.verified;
      q.p->residuals = q.residuals;
    }
  }
};

/// RMS pattern residual (grey levels) of the inlier residuals hosted by `hosts`, as last evaluated.
double inlierRmse(const std::vector<std::unique_ptr<WindowKeyframe>>& hosts) {
  double energy = 0.0;
  long count = 0;
  for (const auto& kf : hosts)
    for (const auto& p : kf->points)
      for (const PointResidual& r : p->residuals)
        if (r.state == ResidualState::Inlier) {
          energy += r.energy;
          ++count;
        }
  return count > 0 ? std::sqrt(energy / (static_cast<double>(count) * kPatternSize)) : 0.0;
}

}  // namespace

Mapper::ReactivationTrial Mapper::tryReactivated() {
  ReactivationTrial t;
  if (window_.size() < 2 || reactivated_.empty()) return t;
  WindowState state;
  for (auto& kf : window_) state.add(*kf);
  for (auto& kf : reactivated_) state.add(*kf);
  optimizer_.evaluate(windowView(), prior_);
  t.own_rmse_before = inlierRmse(window_);
  optimizer_.optimize(windowView(), prior_);
  t.own_rmse_after = inlierRmse(window_);
  t.fits = measureReactivatedFit();
  state.restore();
  return t;
}

}  // namespace ldsm
