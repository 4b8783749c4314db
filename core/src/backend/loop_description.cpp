#include "backend/loop_description.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>

#include "backend/active_point.h"

namespace ldsm {

namespace {

/// Projected active points in a coarse grid of the keyframe's image.
class ProjectedPoints {
 public:
  ProjectedPoints(int width, int height, float cell)
      : cell_(cell),
        cols_(std::max(1, static_cast<int>(std::ceil(static_cast<float>(width) / cell)))),
        rows_(std::max(1, static_cast<int>(std::ceil(static_cast<float>(height) / cell)))),
        cells_(static_cast<std::size_t>(cols_ * rows_)) {}

  void add(float u, float v, float idepth) {
    const int cx = static_cast<int>(u / cell_), cy = static_cast<int>(v / cell_);
    if (cx < 0 || cy < 0 || cx >= cols_ || cy >= rows_) return;
    cells_[static_cast<std::size_t>(cy * cols_ + cx)].push_back({u, v, idepth});
  }

  /// Inverse depths of the points within `radius` of (u, v), into `out`.
  void near(float u, float v, float radius, std::vector<float>& out) const {
    out.clear();
    const int x0 = std::max(0, static_cast<int>((u - radius) / cell_));
    const int x1 = std::min(cols_ - 1, static_cast<int>((u + radius) / cell_));
    const int y0 = std::max(0, static_cast<int>((v - radius) / cell_));
    const int y1 = std::min(rows_ - 1, static_cast<int>((v + radius) / cell_));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x)
        for (const Entry& e : cells_[static_cast<std::size_t>(y * cols_ + x)]) {
          const float du = e.u - u, dv = e.v - v;
          if (du * du + dv * dv <= radius * radius) out.push_back(e.idepth);
        }
  }

 private:
  struct Entry {
    float u, v, idepth;
  };
  float cell_;
  int cols_, rows_;
  std::vector<std::vector<Entry>> cells_;
};

}  // namespace

CornerDepthFill fillCornerDepths(WindowKeyframe& kf,
                                 const std::vector<std::unique_ptr<WindowKeyframe>>& window,
                                 const LevelCamera& camera) {
  CornerDepthFill fill;
  const std::size_t n = kf.corners.size();
  kf.corner_idepth.resize(n, std::numeric_limits<float>::quiet_NaN());
  std::size_t missing = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (std::isfinite(kf.corner_idepth[i])) {
      ++fill.from_points;
    } else {
      ++missing;
    }
  }
  if (missing == 0) return fill;

  // 1. Converged immature corners (the immature list keeps the selection order of the corners).
  std::size_t corner = 0;
  for (const ImmatureCandidate& c : kf.immature) {
    if (!c.is_corner) continue;
    while (corner < n &&
           (kf.corners[corner].x() != c.point.u() || kf.corners[corner].y() != c.point.v()))
      ++corner;
    if (corner >= n) break;
    float& d = kf.corner_idepth[corner];
    if (!std::isfinite(d) &&
        c.point.isConverged(CornerDepthFill::kMaxRelativeWidth, CornerDepthFill::kMinQuality)) {
      d = c.point.idepthEstimate();
      ++fill.from_immature;
    }
    ++corner;
  }

  // 2. The window's active points projected into the keyframe.
  ProjectedPoints grid(camera.width, camera.height, 2.f * CornerDepthFill::kNeighbourRadius);
  for (const auto& host : window) {
    const SE3f T_kf_host = (kf.T_c_w * host->T_c_w.inverse()).cast<float>();
    for (const auto& p : host->points) {
      if (!(p->idepth > 0.f)) continue;
      const Eigen::Vector3f q = T_kf_host * (camera.unproject(p->u, p->v) / p->idepth);
      if (!(q.z() > 1e-6f)) continue;
      const Eigen::Vector2f uv = camera.project(q);
      grid.add(uv.x(), uv.y(), 1.f / q.z());
    }
  }
  std::vector<float> near;
  for (std::size_t i = 0; i < n; ++i) {
    float& d = kf.corner_idepth[i];
    if (std::isfinite(d)) continue;
    grid.near(kf.corners[i].x(), kf.corners[i].y(), CornerDepthFill::kNeighbourRadius, near);
    if (static_cast<int>(near.size()) < CornerDepthFill::kMinNeighbours) {
      ++fill.without;
      continue;
    }
    const auto [lo, hi] = std::minmax_element(near.begin(), near.end());
    if (!(*lo > 0.f) || *hi > CornerDepthFill::kMaxSpread * *lo) {
      ++fill.without;
      continue;
    }
    std::nth_element(near.begin(), near.begin() + static_cast<std::ptrdiff_t>(near.size() / 2),
                     near.end());
    d = near[near.size() / 2];
    ++fill.from_neighbours;
  }
  return fill;
}

void appendLoopCorners(const std::vector<Eigen::Vector2f>& loop_corners,
                       std::vector<Eigen::Vector2f>& corners) {
  const std::size_t own = corners.size();
  for (const Eigen::Vector2f& c : loop_corners) {
    bool taken = false;
    for (std::size_t i = 0; i < own && !taken; ++i) taken = (corners[i] - c).squaredNorm() < 16.f;
    if (!taken) corners.push_back(c);
  }
}

void describeForLoopClosure(WindowKeyframe& f,
                            const std::vector<std::unique_ptr<WindowKeyframe>>& window,
                            const LevelCamera& camera, MarginalizedKeyframe& out) {
  const std::size_t own = f.corners.size();
  appendLoopCorners(f.loop_corners, f.corners);
  const CornerDepthFill fill = fillCornerDepths(f, window, camera);
  spdlog::debug(
      "keyframe {} leaves: {} odometry + {} more corners ({} detected); depths: {} own, {} "
      "immature, {} nearby, {} none",
      f.id(), own, f.corners.size() - own, f.loop_corners.size(), fill.from_points,
      fill.from_immature, fill.from_neighbours, fill.without);
  out.corners = f.corners;
  out.corner_idepth = f.corner_idepth;
}

}  // namespace ldsm
