#include "reuse/relocalizer.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "camera/radial_distortion.h"
#include "features/orb_matching.h"
#include "math/constants.h"

namespace ldsm {
namespace {

constexpr int kMaxCorners = 500;
constexpr float kCornerMinScore = 9.f;  // as loop closure describes keyframes
constexpr int kTriedCandidates = 5;     // best by ORB matches, through PnP and direct alignment
// Least mean correlation of the map keyframe's patterns with the frame's where the direct fit puts
// them: the right place correlates well (with its occlusions and blur), unrelated intensities not
// at all, even when the fit flattens the contrast to make its residuals small.
constexpr double kMinPatternCorrelation = 0.3;
// The same for a fit from the keyframe's own pose, where no PnP pose backs it: the right place
// correlates 0.85-0.9 (vamr_desk_loop after a gap); a fit that wandered 12 degrees off to a
// look-alike of the checkerboard, 0.53 with 71 % inliers.
constexpr double kMinPatternCorrelationWithoutPnp = 0.7;

/// Debug line: where a map keyframe's fit ended (`fit`) relative to `reference`, in median depths
/// and degrees; `what` names the reference.
void logFitOffset(const char* check, int keyframe_id, const SE3d& fit, const SE3d& reference,
                  double median_depth, const std::string& what) {
  const SE3d d = fit * reference.inverse();
  spdlog::debug("relocalisation{}: keyframe {} aligns {:.3f} median depths and {:.2f} degrees {}",
                check, keyframe_id, d.translation().norm() / std::max(median_depth, 1e-9),
                degrees(d.so3().log().norm()), what);
}

}  // namespace

Relocalizer::Relocalizer(const ReuseConfig& config, const PyramidCamera& camera)
    : config_(config), camera_(camera), orb_(camera[0].width, camera[0].height) {
  pnp_.min_inliers = config.relocalization_min_inliers;
  pnp_.inlier_threshold_px = 4.0;
  // A relocalisation uses a PnP pose only with min_inliers: after a gap most candidates have a few
  // right matches of about 20 (vamr_desk_loop: 4-6), and the full 1000 samples on each of five
  // candidates were a third of a relocalisation attempt's instructions.
  pnp_.cap_samples_for_min_inliers = true;
  direct_.min_inlier_fraction = config.relocalization_min_direct_inliers;
}

bool Relocalizer::describeFrame(const ImagePyramid& frame, std::string& failure) {
  CornerParams params;
  params.max_corners = kMaxCorners;
  params.min_score = kCornerMinScore;
  if (!corners_) corners_.emplace(camera_[0].width, camera_[0].height);
  corners_->detect(frame.gradients(0), params, corner_scratch_);
  pixels_.clear();
  for (const Corner& c : corner_scratch_) pixels_.emplace_back(c.u, c.v);
  orb_.compute(frame.gradients(0), pixels_, descriptors_, kept_);
  if (descriptors_.size() >= static_cast<std::size_t>(pnp_.min_inliers)) return true;
  failure = "only " + std::to_string(descriptors_.size()) + " corners in the frame";
  return false;
}

std::vector<int> Relocalizer::candidates(const MapStore& map, const SE3d& last_T_c_w,
                                         const std::vector<int>& recent_ids,
                                         double median_depth) const {
  const Eigen::Vector3d centre = last_T_c_w.inverse().translation();
  const double radius = config_.relocalization_search_radius * std::max(median_depth, 1e-3);
  std::vector<int> ids = map.keyframesNear(centre, radius);
  const std::size_t near_limit = static_cast<std::size_t>(config_.relocalization_near_candidates);
  if (ids.size() > near_limit) {
    // The nearest first (ties by id, so that the order never depends on the store's layout).
    std::vector<std::pair<double, int>> by_distance;
    by_distance.reserve(ids.size());
    for (const int id : ids)
      by_distance.push_back({(map.keyframe(id).T_w_c.translation() - centre).squaredNorm(), id});
    std::partial_sort(by_distance.begin(),
                      by_distance.begin() + static_cast<std::ptrdiff_t>(near_limit),
                      by_distance.end());
    ids.clear();
    for (std::size_t i = 0; i < near_limit; ++i) ids.push_back(by_distance[i].second);
  }
  const std::size_t near = ids.size();
  for (const int id : map.covisibleNeighbourhood(recent_ids, config_.search_hops,
                                                 static_cast<std::size_t>(config_.max_candidates)))
    if (std::find(ids.begin(), ids.end(), id) == ids.end()) ids.push_back(id);
  const std::size_t covisible = ids.size() - near;
  for (const int id : recent_ids)
    if (map.keyframeData(id) && std::find(ids.begin(), ids.end(), id) == ids.end())
      ids.push_back(id);
  spdlog::debug(
      "relocalisation candidates: {} nearest within {:.2f} of the last pose, {} more covisible "
      "with the "
      "window, {} more of the window",
      near, radius, covisible, ids.size() - near - covisible);
  return ids;
}

std::vector<std::pair<int, int>> Relocalizer::rankByMatches(const MapStore& map,
                                                            const std::vector<int>& ids) const {
  std::vector<std::pair<int, int>> scored;  // (matches, id)
  for (const int id : ids) {
    const std::shared_ptr<const MarginalizedKeyframe> kf = map.keyframeData(id);
    if (!kf) continue;
    int n = 0;
    for (const auto& [q, t] : matchOrb(descriptors_, kf->descriptors))
      if (t < static_cast<int>(kf->corner_idepth.size()) && kf->corner_idepth[t] > 0.f) ++n;
    scored.push_back({n, id});
  }
  std::stable_sort(scored.begin(), scored.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  return scored;
}

PnpRansacResult Relocalizer::solvePnp(const MarginalizedKeyframe& kf, const KeyframeRecord& pose,
                                      RelocalizationResult& out) const {
  const LevelCamera& cam = camera_[0];
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector2d> pixels;
  for (const auto& [q, t] : matchOrb(descriptors_, kf.descriptors)) {
    if (t >= static_cast<int>(kf.corner_idepth.size())) continue;
    const float d = kf.corner_idepth[t];
    if (!(d > 0.f) || !std::isfinite(d)) continue;
    const Eigen::Vector2f& c = kf.corners[t];
    points.push_back(pose.scale * radialRay(cam, kf.radial_k, c.x(), c.y()).cast<double>() /
                     static_cast<double>(d));
    pixels.push_back(pixels_[kept_[q]].cast<double>());
  }
  const PinholeIntrinsics pinhole{cam.fx, cam.fy, cam.cx, cam.cy, cam.width, cam.height};
  PnpRansacResult pnp = solvePnpRansac(points, pixels, pinhole, pnp_);
  out.matches = static_cast<int>(points.size());
  out.pnp_inliers = static_cast<int>(pnp.inliers.size());
  if (!pnp.success)
    out.failure = "PnP against keyframe " + std::to_string(kf.id) + ": " +
                  std::to_string(pnp.inliers.size()) + " inliers of " +
                  std::to_string(points.size());
  return pnp;
}

DirectAlignmentResult Relocalizer::alignDirectly(const MarginalizedKeyframe& kf,
                                                 const KeyframeRecord& pose,
                                                 const ImagePyramid& frame, double exposure,
                                                 const SE3d& T_start,
                                                 bool from_keyframe_pose) const {
  std::vector<PatchPoint> scaled = kf.points;
  for (PatchPoint& p : scaled) p.idepth /= static_cast<float>(pose.scale);
  const Eigen::Vector2d transfer = affineTransfer(kf.exposure, exposure, kf.aff, AffineLight{});
  DirectAlignmentResult direct = alignPoints(scaled, camera_, kf.radial_k, frame, T_start,
                                             std::log(transfer[0]), transfer[1], direct_);
  spdlog::debug(
      "relocalisation: keyframe {}: {} of {} points, pattern correlation {:.2f}, "
      "brightness scale {:.2f} (exposures: {:.2f})",
      kf.id, direct.inliers, direct.in_image, direct.pattern_correlation, std::exp(direct.a),
      transfer[0]);
  const double min_correlation =
      from_keyframe_pose ? kMinPatternCorrelationWithoutPnp : kMinPatternCorrelation;
  if (direct.success && !(direct.pattern_correlation >= min_correlation)) {
    direct.success = false;
    direct.failure =
        fmt::format("its patterns correlate {:.2f} with the frame's (brightness scale {:.2f})",
                    direct.pattern_correlation, std::exp(direct.a));
  }
  return direct;
}

RelocalizationResult Relocalizer::relocalize(const ImagePyramid& frame, double exposure,
                                             const MapStore& map, const SE3d& last_T_c_w,
                                             const std::vector<int>& recent_ids,
                                             double median_depth, const PlaceQuery& places) {
  RelocalizationResult out;
  if (!describeFrame(frame, out.failure)) return out;
  std::vector<int> ids = candidates(map, last_T_c_w, recent_ids, median_depth);
  if (places)
    for (const int id : places(descriptors_))
      if (std::find(ids.begin(), ids.end(), id) == ids.end()) ids.push_back(id);
  const std::vector<std::pair<int, int>> scored = rankByMatches(map, ids);
  if (scored.empty()) {
    out.failure = "no map keyframe to look in";
    return out;
  }
  RelocalizationResult best;
  double best_angle = 0.0;
  struct PnpFailure {
    std::shared_ptr<const MarginalizedKeyframe> kf;
    KeyframeRecord pose;
    RelocalizationResult counts;  ///< its match counts and PnP failure
  };
  std::vector<PnpFailure> pnp_failed;
  for (int k = 0; k < kTriedCandidates && k < static_cast<int>(scored.size()); ++k) {
    const auto [matches, id] = scored[static_cast<std::size_t>(k)];
    if (matches < pnp_.min_inliers) {
      if (k == 0)
        out.failure = "best map keyframe " + std::to_string(id) + " has " +
                      std::to_string(matches) + " ORB matches with a depth, fewer than " +
                      std::to_string(pnp_.min_inliers);
      break;
    }
    const std::shared_ptr<const MarginalizedKeyframe> kf = map.keyframeData(id);
    const KeyframeRecord pose = map.keyframe(id);
    if (!kf || pose.id < 0) {
      out.failure = "map keyframe " + std::to_string(id) + " has no pose";
      continue;
    }
    const PnpRansacResult pnp = solvePnp(*kf, pose, out);
    if (pnp.success) {
      considerFit(*kf, pose, frame, exposure, pnp.T_camera_points, false, out, best, best_angle);
    } else if (config_.relocalization_direct_start) {
      pnp_failed.push_back({kf, pose, out});
    }
  }
  // PnP fails where most matches are wrong although the keyframe shows the place (a repeated
  // texture: vamr_desk_loop's checkerboard after a gap, 8-14 PnP inliers of 23 matches). Where no
  // fit from a PnP pose held, those candidates are aligned directly from their own poses: coarse
  // to fine, that converges when the camera is near the viewpoint, and it must pass the same
  // checks with a stronger pattern correlation.
  if (!best.success)
    for (const PnpFailure& c : pnp_failed)
      considerFit(*c.kf, c.pose, frame, exposure, SE3d(), true, c.counts, best, best_angle);
  if (!best.success && best.failure.empty()) best.failure = out.failure;
  if (best.success) refineFromNearer(frame, exposure, map, median_depth, best);
  return best;
}

void Relocalizer::considerFit(const MarginalizedKeyframe& kf, const KeyframeRecord& pose,
                              const ImagePyramid& frame, double exposure, const SE3d& T_start,
                              bool from_keyframe_pose, const RelocalizationResult& counts,
                              RelocalizationResult& best, double& best_angle) const {
  const DirectAlignmentResult direct =
      alignDirectly(kf, pose, frame, exposure, T_start, from_keyframe_pose);
  if (!direct.success) {
    // While nothing has held, the last failure says why.
    if (!best.success) {
      best.failure =
          (from_keyframe_pose ? counts.failure + "; direct alignment from its pose: "
                              : "direct alignment to keyframe " + std::to_string(kf.id) + ": ") +
          direct.failure;
      best.direct_inliers = direct.inliers;
      best.direct_points = direct.in_image;
      best.matches = counts.matches;
      best.pnp_inliers = counts.pnp_inliers;
    }
    return;
  }
  // Of the candidates that hold, the one seen from the nearest viewpoint: the photometric
  // alignment (an unwarped pattern, the map's depths) is most accurate there.
  const double angle = direct.T_target_host.so3().log().norm();
  if (best.success && angle >= best_angle) return;
  best_angle = angle;
  best = counts;
  best.success = true;
  best.failure.clear();
  best.keyframe_id = kf.id;
  best.from_keyframe_pose = from_keyframe_pose;
  best.direct_inliers = direct.inliers;
  best.direct_points = direct.in_image;
  best.T_c_w = direct.T_target_host * pose.T_w_c.inverse();
  best.aff = frameBrightness(direct, kf, exposure);
}

AffineLight Relocalizer::frameBrightness(const DirectAlignmentResult& direct,
                                         const MarginalizedKeyframe& kf, double exposure) {
  // The frame's own affine brightness from the transfer keyframe -> frame
  // (scale e^a = e^(a_f - a_k) t_f / t_k, offset b = b_f - scale b_k).
  AffineLight aff;
  aff.a = direct.a - std::log(exposure / kf.exposure) + kf.aff.a;
  aff.b = direct.b + std::exp(direct.a) * kf.aff.b;
  return aff;
}

void Relocalizer::refineFromNearer(const ImagePyramid& frame, double exposure, const MapStore& map,
                                   double median_depth, RelocalizationResult& best) const {
  const KeyframeRecord found = map.keyframe(best.keyframe_id);
  const double found_distance =
      (found.T_w_c.translation() - best.T_c_w.inverse().translation()).norm();
  const int found_id = best.keyframe_id;
  best.found_keyframe_id = found_id;
  if (alignNearest(frame, exposure, map, best.T_c_w, median_depth, found_id, found_distance, {},
                   best))
    spdlog::debug("relocalisation: refined against keyframe {} (keyframe {}: {:.3f} away)",
                  best.keyframe_id, found_id, found_distance);
}

RelocalizationResult Relocalizer::confirm(const ImagePyramid& frame, double exposure,
                                          const MapStore& map, const SE3d& T_c_w,
                                          double median_depth,
                                          const std::function<bool(const SE3d&)>& agrees) const {
  RelocalizationResult out;
  if (alignNearest(frame, exposure, map, T_c_w, median_depth, -1,
                   std::numeric_limits<double>::infinity(), agrees, out)) {
    out.success = true;
    return out;
  }
  out.failure = "no map keyframe near the pose aligns to the frame there";
  return out;
}

bool Relocalizer::forEachNearestFit(const ImagePyramid& frame, double exposure, const MapStore& map,
                                    const SE3d& T_c_w, double median_depth, int skip_id,
                                    double max_distance,
                                    const std::function<bool(const RelocalizationResult&)>& visit,
                                    int also_skip_id) const {
  constexpr int kTriedNearest = 3;
  const Eigen::Vector3d centre = T_c_w.inverse().translation();
  struct Near {
    double distance;
    int id;
    KeyframeRecord pose;
    std::shared_ptr<const MarginalizedKeyframe> kf;  // held: the mapping thread may cull it
  };
  std::vector<Near> nearest;
  for (const int id :
       candidates(map, T_c_w, skip_id >= 0 ? std::vector<int>{skip_id} : std::vector<int>{},
                  median_depth)) {
    if (id == skip_id || id == also_skip_id) continue;
    const KeyframeRecord r = map.keyframe(id);
    std::shared_ptr<const MarginalizedKeyframe> kf = map.keyframeData(id);
    if (r.id < 0 || !kf || kf->points.empty()) continue;
    const double d = (r.T_w_c.translation() - centre).norm();
    if (d < max_distance) nearest.push_back({d, id, r, std::move(kf)});
  }
  std::sort(nearest.begin(), nearest.end(), [](const Near& a, const Near& b) {
    return a.distance < b.distance || (a.distance == b.distance && a.id < b.id);
  });
  for (int k = 0; k < kTriedNearest && k < static_cast<int>(nearest.size()); ++k) {
    const Near& n = nearest[static_cast<std::size_t>(k)];
    const DirectAlignmentResult direct =
        alignDirectly(*n.kf, n.pose, frame, exposure, T_c_w * n.pose.T_w_c);
    if (!direct.success) continue;
    RelocalizationResult fit;
    fit.success = true;
    fit.keyframe_id = n.id;
    fit.direct_inliers = direct.inliers;
    fit.direct_points = direct.in_image;
    fit.T_c_w = direct.T_target_host * n.pose.T_w_c.inverse();
    fit.aff = frameBrightness(direct, *n.kf, exposure);
    if (visit(fit)) return true;
  }
  return false;
}

bool Relocalizer::alignNearest(const ImagePyramid& frame, double exposure, const MapStore& map,
                               const SE3d T_c_w, double median_depth, int skip_id,
                               double max_distance, const std::function<bool(const SE3d&)>& accept,
                               RelocalizationResult& out) const {
  return forEachNearestFit(frame, exposure, map, T_c_w, median_depth, skip_id, max_distance,
                           [&](const RelocalizationResult& fit) {
                             if (accept && !accept(fit.T_c_w)) {
                               logFitOffset("", fit.keyframe_id, fit.T_c_w, T_c_w, median_depth,
                                            "away");
                               return false;
                             }
                             out.keyframe_id = fit.keyframe_id;
                             out.direct_inliers = fit.direct_inliers;
                             out.direct_points = fit.direct_points;
                             out.T_c_w = fit.T_c_w;
                             out.aff = fit.aff;
                             return true;
                           });
}

Relocalizer::CrossCheck Relocalizer::crossCheck(
    const ImagePyramid& frame, double exposure, const MapStore& map, double median_depth,
    const std::function<bool(const SE3d&, const SE3d&)>& agree,
    const RelocalizationResult& answer) const {
  int there = 0, elsewhere = 0;
  const auto vote = [&](const RelocalizationResult& fit) {
    if (agree(fit.T_c_w, answer.T_c_w)) {
      ++there;
      return false;
    }
    logFitOffset(" cross-check", fit.keyframe_id, fit.T_c_w, answer.T_c_w, median_depth,
                 "from the answer (keyframe " + std::to_string(answer.keyframe_id) + ")");
    ++elsewhere;
    return false;
  };
  forEachNearestFit(frame, exposure, map, answer.T_c_w, median_depth, answer.keyframe_id,
                    std::numeric_limits<double>::infinity(), vote, answer.found_keyframe_id);
  if (there == 0 && elsewhere == 0) return CrossCheck::kUnchecked;
  return there > elsewhere ? CrossCheck::kConfirmed : CrossCheck::kRefused;
}

}  // namespace ldsm
