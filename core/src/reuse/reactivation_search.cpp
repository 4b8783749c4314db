#include "reuse/reactivation_search.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <spdlog/spdlog.h>

#include "alignment/direct_alignment.h"
#include "camera/radial_distortion.h"
#include "features/orb_matching.h"
#include "math/constants.h"

namespace ldsm {
namespace {

constexpr float kBorder = 4.f;

/// The world point of a host pixel with inverse depth (in the host's original units) for a map
/// keyframe at pose (R, t) and scale s: X_w = R (s X_c) + t.
Eigen::Vector3d worldPoint(const LevelCamera& cam, float k, float u, float v, float idepth,
                           const KeyframeRecord& pose) {
  const Eigen::Vector3d X = radialRay(cam, k, u, v).cast<double>() / static_cast<double>(idepth);
  return pose.T_w_c * (pose.scale * X);
}

bool projectInto(const ReuseView& view, const Eigen::Vector3d& X_w, Eigen::Vector2f* px) {
  const Eigen::Vector3d X = view.T_c_w * X_w;
  if (!(X.z() > 1e-6)) return false;
  *px = radialProject(view.camera, view.radial_k, X.cast<float>());
  return px->x() >= kBorder && px->y() >= kBorder &&
         px->x() <= static_cast<float>(view.camera.width) - 1.f - kBorder &&
         px->y() <= static_cast<float>(view.camera.height) - 1.f - kBorder;
}

/// The mean distance between the projections of the points under two host-to-view poses.
double meanShift(const ReuseView& view, float host_k, const std::vector<PatchPoint>& points,
                 const SE3d& T_a, const SE3d& T_b) {
  double shift = 0.0;
  int shifted = 0;
  for (const PatchPoint& p : points) {
    const Eigen::Vector3d X = radialRay(view.camera, host_k, p.u, p.v).cast<double>() / p.idepth;
    const Eigen::Vector3d a = T_a * X;
    const Eigen::Vector3d b = T_b * X;
    if (!(a.z() > 1e-6) || !(b.z() > 1e-6)) continue;
    shift += (radialProject(view.camera, view.radial_k, a.cast<float>()) -
              radialProject(view.camera, view.radial_k, b.cast<float>()))
                 .norm();
    ++shifted;
  }
  return shifted > 0 ? shift / shifted : 0.0;
}

}  // namespace

std::vector<int> ReactivationSearch::candidates(const ReuseView& view, const MapStore& map,
                                                const std::vector<int>& exclude) const {
  std::vector<int> ids = map.covisibleNeighbourhood(
      view.window_ids, config_.search_hops, static_cast<std::size_t>(4 * config_.max_candidates));
  const Eigen::Vector3d centre = view.T_c_w.inverse().translation();
  for (const int id : map.keyframesNear(centre, config_.search_radius * view.median_depth))
    if (std::find(ids.begin(), ids.end(), id) == ids.end()) ids.push_back(id);
  spdlog::trace("reuse: {} covisible or near (radius {:.3f})", ids.size(),
                config_.search_radius * view.median_depth);
  std::vector<int> out;
  for (const int id : ids) {
    if (std::find(exclude.begin(), exclude.end(), id) != exclude.end()) continue;
    out.push_back(id);
  }
  // Nearest in time to the spatial neighbours first would favour the drifted past; keep the
  // candidates in id order for determinism and cap them.
  std::sort(out.begin(), out.end());
  if (out.size() > static_cast<std::size_t>(config_.max_candidates)) {
    // Prefer the spatially nearest ones.
    std::vector<std::pair<double, int>> by_distance;
    for (const int id : out) {
      const KeyframeRecord r = map.keyframe(id);
      by_distance.push_back({(r.T_w_c.translation() - centre).squaredNorm(), id});
    }
    std::sort(by_distance.begin(), by_distance.end());
    out.clear();
    for (int i = 0; i < config_.max_candidates; ++i) out.push_back(by_distance[i].second);
    std::sort(out.begin(), out.end());
  }
  return out;
}

ReuseCheck ReactivationSearch::check(const ReuseView& view, const MarginalizedKeyframe& keyframe,
                                     const KeyframeRecord& pose, bool direct) const {
  ReuseCheck c;
  c.id = keyframe.id;
  // 0. A revisit, not the odometry's own recent past: it left the window long enough ago.
  if (keyframe.newest_when_left > view.keyframe_id - config_.min_keyframe_age) {
    c.reason = "left the window " + std::to_string(view.keyframe_id - keyframe.newest_when_left) +
               " keyframes ago";
    return c;
  }
  // The camera came back: a long way round, or (nearly) the same place.
  const double chord = (pose.T_w_c.translation() - view.T_c_w.inverse().translation()).norm();
  const double travelled = view.path_length - keyframe.path_length;
  const bool earlier_chain = keyframe.id < view.chain_start_id;
  if (!earlier_chain && !(chord < config_.same_place_distance * view.median_depth ||
                          travelled > config_.revisit_ratio * chord)) {
    c.reason = "not a revisit (travelled " + std::to_string(travelled) + ", " +
               std::to_string(chord) + " away)";
    return c;
  }
  c.stage = ReuseStage::Geometry;
  // 1. Looking the same way.
  const Eigen::Vector3d axis_kf = pose.T_w_c.so3() * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d axis_view = view.T_c_w.inverse().so3() * Eigen::Vector3d::UnitZ();
  const double angle = degrees(std::acos(std::clamp(axis_kf.dot(axis_view), -1.0, 1.0)));
  if (angle > config_.max_view_angle_deg) {
    c.reason = "viewing angle " + std::to_string(angle) + " deg";
    return c;
  }
  // 2. Geometric check: its points in the current view.
  for (const PatchPoint& p : keyframe.points) {
    Eigen::Vector2f px;
    if (projectInto(view, worldPoint(view.camera, keyframe.radial_k, p.u, p.v, p.idepth, pose),
                    &px))
      ++c.in_view;
  }
  c.overlap = keyframe.points.empty()
                  ? 0.0
                  : static_cast<double>(c.in_view) / static_cast<double>(keyframe.points.size());
  if (c.in_view < config_.min_points_in_view || c.overlap < config_.min_overlap) {
    c.reason = std::to_string(c.in_view) + " points in view (" +
               std::to_string(static_cast<int>(100 * c.overlap)) + " %)";
    return c;
  }
  c.stage = ReuseStage::Features;
  // 3. Feature check: ORB matches that agree with the projection.
  const float r2 = static_cast<float>(config_.feature_radius_px * config_.feature_radius_px);
  const std::vector<std::pair<int, int>> matches = matchOrb(view.descriptors, keyframe.descriptors);
  int with_depth = 0;
  for (const auto& [q, t] : matches) {
    if (t >= static_cast<int>(keyframe.corner_idepth.size())) continue;
    const float d = keyframe.corner_idepth[t];
    if (!(d > 0.f) || !std::isfinite(d)) continue;
    ++with_depth;
    const Eigen::Vector2f& corner = keyframe.corners[t];
    Eigen::Vector2f px;
    if (!projectInto(
            view, worldPoint(view.camera, keyframe.radial_k, corner.x(), corner.y(), d, pose), &px))
      continue;
    if ((px - view.corners[q]).squaredNorm() <= r2) ++c.matches;
  }
  if (c.matches < config_.min_feature_matches) {
    c.reason = std::to_string(c.matches) + " consistent ORB matches (of " +
               std::to_string(matches.size()) + ", " + std::to_string(with_depth) +
               " with depth; " + std::to_string(view.descriptors.size()) + " x " +
               std::to_string(keyframe.descriptors.size()) + " descriptors)";
    return c;
  }
  c.stage = ReuseStage::Direct;
  c.direct_skipped = true;  // neither accepted nor rejected until finishCheck() aligns it
  if (direct) finishCheck(view, keyframe, pose, c);
  return c;
}

bool ReactivationSearch::finishCheck(const ReuseView& view, const MarginalizedKeyframe& keyframe,
                                     const KeyframeRecord& pose, ReuseCheck& c) const {
  c.direct_skipped = false;
  if (config_.direct_check && view.pyramid && view.pyramid_camera &&
      !checkDirect(view, keyframe, pose, c))
    return false;
  c.stage = ReuseStage::Accepted;
  c.accepted = true;
  return true;
}

bool ReactivationSearch::checkDirect(const ReuseView& view, const MarginalizedKeyframe& keyframe,
                                     const KeyframeRecord& pose, ReuseCheck& c) const {
  // 4. Direct check: align the candidate's points to the newest keyframe, starting from the
  // relative pose the window (newest keyframe) and the map (candidate) give.
  std::vector<PatchPoint> points = keyframe.points;
  const float inv_scale = static_cast<float>(1.0 / pose.scale);
  for (PatchPoint& p : points) p.idepth *= inv_scale;
  const SE3d T_view_kf = view.T_c_w * pose.T_w_c;
  const Eigen::Vector2d transfer =
      affineTransfer(keyframe.exposure, view.exposure, keyframe.aff, view.aff);
  DirectAlignmentSettings settings;
  settings.min_inlier_fraction = config_.direct_min_inliers;
  const DirectAlignmentResult d =
      alignPoints(points, *view.pyramid_camera, keyframe.radial_k, *view.pyramid, T_view_kf,
                  std::log(transfer[0]), transfer[1], settings);
  c.direct_inliers =
      d.in_image > 0 ? static_cast<double>(d.inliers) / static_cast<double>(d.in_image) : 0.0;
  c.correlation = d.pattern_correlation;
  c.shift_px = meanShift(view, keyframe.radial_k, points, T_view_kf, d.T_target_host);
  if (d.success && config_.direct_basin_px > 0.0 && c.shift_px > config_.direct_basin_px) {
    // Within the basin of the window's full-resolution optimisation?
    DirectAlignmentSettings fine = settings;
    fine.coarsest_level = 0;
    const DirectAlignmentResult f =
        alignPoints(points, *view.pyramid_camera, keyframe.radial_k, *view.pyramid, T_view_kf,
                    std::log(transfer[0]), transfer[1], fine);
    c.basin_miss_px = meanShift(view, keyframe.radial_k, points, f.T_target_host, d.T_target_host);
  }
  if (!d.success) {
    c.reason = "direct alignment failed (" + d.failure + ")";
    return false;
  }
  c.T_view_kf_aligned = d.T_target_host;
  const bool fits =
      c.direct_inliers >= config_.direct_min_inliers &&
      c.correlation >= config_.direct_min_correlation &&
      (config_.direct_max_shift_px <= 0.0 || c.shift_px <= config_.direct_max_shift_px);
  if (fits && (config_.direct_basin_px <= 0.0 || c.basin_miss_px <= config_.direct_basin_px))
    return true;
  c.outside_basin = fits;
  char detail[200];
  std::snprintf(detail, sizeof(detail),
                "%d of %d points fit (%.0f %%), pattern correlation %.2f, %.2f px from the "
                "window's pose, full resolution alone misses by %.2f px",
                d.inliers, d.in_image, 100.0 * c.direct_inliers, c.correlation, c.shift_px,
                c.basin_miss_px);
  c.reason = std::string("direct check: ") + detail;
  return false;
}

std::vector<ReuseCheck> ReactivationSearch::search(const ReuseView& view, const MapStore& map,
                                                   const std::vector<int>& exclude,
                                                   bool direct) const {
  std::vector<ReuseCheck> out;
  for (const int id : candidates(view, map, exclude)) {
    const std::shared_ptr<const MarginalizedKeyframe> data = map.keyframeData(id);
    if (!data) continue;
    out.push_back(check(view, *data, map.keyframe(id), direct));
  }
  std::stable_sort(out.begin(), out.end(), [](const ReuseCheck& a, const ReuseCheck& b) {
    if (a.accepted != b.accepted) return a.accepted;
    return a.matches > b.matches;
  });
  return out;
}

}  // namespace ldsm
