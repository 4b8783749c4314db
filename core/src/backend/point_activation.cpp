// Activation of immature points (part of the Mapper): candidates whose depth interval converged
// become active points when they fall where the newest keyframe has no active point nearby. The
// spacing adapts so that the window keeps about window.active_points points.
#include <algorithm>
#include <cmath>

#include "backend/mapper.h"

namespace ldsm {

bool Mapper::optimizeNewPointDepth(ActivePoint& point, const std::vector<FramePairPrecalc>& pairs) {
  const int n = static_cast<int>(window_.size());
  const int h = point.host->window_index;
  const ResidualSettings& rs = optimizer_.settings().residual;
  // The pairs are the optimiser's (framePairs()): the point's host ray is the same in all of them.
  const Eigen::Vector2f host = optimizer_.hostPixel(point);
  auto evaluate = [&](bool linearize, double* H, double* b) {
    double energy = 0.0;
    *H = *b = 0.0;
    for (auto& r : point.residuals) {
      ResidualAccumulator acc;
      acc.depth_only = true;
      const FramePairPrecalc& pair = pairs[static_cast<size_t>(h) * n + r.target->window_index];
      const float e = evaluateResidual(point, host, r, pair, rs, linearize ? &acc : nullptr);
      energy += r.state == ResidualState::Inlier ? e : outlierEnergy(pair, rs);
      *H += acc.H_dd;
      *b += acc.b_d;
    }
    return energy;
  };
  double H = 0, b = 0;
  double energy = evaluate(true, &H, &b);
  double lambda = 0.1;
  // Whether the residuals' states (and H) are those of the current depth: after a rejected step
  // they are the trial's, and the depth's are evaluated once more at the end.
  bool evaluated_here = true;
  // Five Gauss-Newton steps. DSO's three cost 30 % less of the activation (the whole of
  // kitti00_200: -1.3 %) at about the same ATE on the real sequences, but the rendered
  // corridor's clean run went 0.0037 -> 0.0054 m and after two seconds without images it no
  // longer resumed in its map (MapReuse.AfterTwoSeconds...: 1.31 m; docs/engine.md, 2026-12-06).
  constexpr int kMaxIterations = 5;
  for (int it = 0; it < kMaxIterations && H > 1e-10; ++it) {
    const float old = point.idepth;
    const double step = -b / (H * (1.0 + lambda));
    point.idepth = std::max(static_cast<float>(std::max(0.25 * old, old + step)), kMinInverseDepth);
    double H2 = 0, b2 = 0;
    const double e2 = evaluate(true, &H2, &b2);
    if (e2 < energy) {
      energy = e2;
      H = H2;
      b = b2;
      lambda *= 0.5;
      evaluated_here = true;
      if (std::fabs(point.idepth - old) < 1e-4f * old) break;
    } else {
      point.idepth = old;
      lambda *= 5.0;
      evaluated_here = false;
    }
  }
  double Hf = H, bf = b;
  if (!evaluated_here) evaluate(true, &Hf, &bf);
  int inliers = 0;
  for (const auto& r : point.residuals) inliers += r.state == ResidualState::Inlier ? 1 : 0;
  point.hessian_idepth = static_cast<float>(Hf);
  point.inlier_residuals = inliers;
  if (inliers == 0 || !(point.idepth > 0.f) || !std::isfinite(point.idepth)) return false;
  // Keep only inlier residuals; the point needs at least one good observation.
  auto& rv = point.residuals;
  rv.erase(std::remove_if(rv.begin(), rv.end(),
                          [](const PointResidual& r) { return r.state != ResidualState::Inlier; }),
           rv.end());
  return Hf > 1e-3;
}

int Mapper::activatePoints() {
  const int n = static_cast<int>(window_.size());
  if (n < 2) return 0;
  for (int i = 0; i < n; ++i) window_[i]->window_index = i;
  WindowKeyframe& newest = *window_.back();
  const LevelCamera& cam = camera_[0];

  // Spacing control: fewer points than wanted -> activate closer to existing ones.
  const int active = activePointCount();
  const double ratio = active / std::max(1.0, static_cast<double>(settings_.window.active_points));
  if (ratio < 0.66)
    min_activation_distance_ -= 0.8f;
  else if (ratio < 0.8)
    min_activation_distance_ -= 0.5f;
  else if (ratio < 0.9)
    min_activation_distance_ -= 0.2f;
  else if (ratio < 1.0)
    min_activation_distance_ -= 0.1f;
  if (ratio > 1.5)
    min_activation_distance_ += 0.8f;
  else if (ratio > 1.3)
    min_activation_distance_ += 0.5f;
  else if (ratio > 1.15)
    min_activation_distance_ += 0.2f;
  else if (ratio > 1.0)
    min_activation_distance_ += 0.1f;
  min_activation_distance_ = std::clamp(min_activation_distance_, 0.f, 4.f);

  DistanceMap& dist = activation_distance_;
  dist.reset((cam.width + 1) / 2, (cam.height + 1) / 2);
  std::vector<DepthPoint> projected;
  trackingPoints(projected);
  for (const auto& p : projected) dist.mark(p.u, p.v);
  dist.propagate();

  // The residuals as the window optimisation evaluates them, radial correction included (until
  // 2026-12-06 the activation's pairs left it at 0: the new depths fitted another camera).
  std::vector<FramePairPrecalc> pairs;
  optimizer_.framePairs(activeView(), pairs);

  // Never grow far beyond the target: the window's cost is linear in the points.
  const int budget = static_cast<int>(1.2 * settings_.window.active_points) - active;
  if (budget <= 0) return 0;
  const float c = optimizer_.settings().residual.gradient_weight_c;
  const float min_quality = static_cast<float>(settings_.window.min_trace_quality);
  const float max_interval = static_cast<float>(settings_.window.max_trace_interval);
  int activated = 0;
  for (int h = 0; h + 1 < n; ++h) {
    WindowKeyframe& kf = *window_[h];
    const SE3f T_nh = (newest.T_c_w * kf.T_c_w.inverse()).cast<float>();
    auto& cands = kf.immature;
    size_t out = 0;
    for (size_t i = 0; i < cands.size(); ++i) {
      ImmaturePoint& ip = cands[i].point;
      bool keep = true;
      const bool converged = ip.lastStatus() != TraceStatus::kUntraced &&
                             ip.lastStatus() != TraceStatus::kOob &&
                             ip.lastStatus() != TraceStatus::kOutlier &&
                             ip.lastPixelInterval() < max_interval && ip.quality() >= min_quality &&
                             ip.idepthMin() + ip.idepthMax() > 0.f && std::isfinite(ip.idepthMax());
      if (converged && activated < budget) {
        const float d = ip.idepthEstimate();
        const Eigen::Vector3f q = T_nh * (radialRay(cam, radialK(), ip.u(), ip.v()) / d);
        const Eigen::Vector2f px = radialProject(cam, radialK(), q);
        const int dd = q.z() > 0 ? dist.at(px.x(), px.y()) : -1;
        if (dd >= 0 && static_cast<float>(dd) >= min_activation_distance_) {
          auto p = std::make_unique<ActivePoint>();
          if (initActivePoint(*p, kf, ip.u(), ip.v(), d, c)) {
            p->is_corner = cands[i].is_corner;
            for (int t = 0; t < n; ++t)
              if (t != h) p->residuals.push_back({window_[t].get()});
            if (optimizeNewPointDepth(*p, pairs)) {
              p->id = next_point_id_++;
              dist.mark(px.x(), px.y());
              kf.points.push_back(std::move(p));
              ++kf.points_created;
              ++activated;
            }
          }
          keep = false;  // activated, or its depth did not hold up: either way it is done
        }
      } else if (ip.lastStatus() == TraceStatus::kOob) {
        keep = false;
      }
      if (keep) {
        if (out != i) cands[out] = std::move(cands[i]);
        ++out;
      }
    }
    cands.erase(cands.begin() + static_cast<std::ptrdiff_t>(out), cands.end());
  }
  return activated;
}

}  // namespace ldsm
