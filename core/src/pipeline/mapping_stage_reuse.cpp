// Map reuse after a keyframe (MappingStage::reuseMap): take back the map keyframes that no longer
// fit, search the map for those that see the newest keyframe, bring them back (replacing a weak
// one when the window's map keyframes are all taken) and, with reuse.trial_check, keep only those
// a trial optimisation confirms.
#include <spdlog/spdlog.h>

#include <algorithm>

#include "pipeline/mapping_stage.h"
#include "reuse/drift_consensus.h"

namespace ldsm {

void MappingStage::reuseMap(int newest_frame_index, double newest_timestamp) {
  // Map keyframes took part in this keyframe's optimisation: the window was on the map.
  if (!mapper_.reactivatedIds().empty()) last_on_map_id_ = mapper_.newestKeyframe().id();
  takeBackMisfits();
  std::vector<std::pair<int, int>> held = replaceableReactivated();
  const int room =
      settings_.reuse.max_reactivated - static_cast<int>(mapper_.reactivatedIds().size());
  const WindowKeyframe& newest = mapper_.newestKeyframe();
  ReuseView view = reuseView(newest);
  // Without room and without a weakened map keyframe to replace, nothing found could come back:
  // the candidates are counted, but not aligned (bringBack would stop at the first accepted).
  const bool can_take = canTake(room, held);
  // The direct check (an alignment, a few milliseconds per candidate) runs on every candidate only
  // where the drift check needs them all; otherwise bringBack runs it on the candidates in order
  // and stops once nothing more can be taken. Both bring back the same keyframes: the accepted
  // candidates are met in the same order (most consistent ORB matches first). In a long revisit
  // of one place most candidates pass and few can come back (the window's map keyframes are all
  // taken): the desk soak's 19th pass checked 9 per keyframe, 61 ms, where 1-2 decide.
  const bool drift_due = driftCheckDue(newest.id(), can_take);
  std::vector<ReuseCheck> checks =
      reuse_->search(view, store_, reuseExclusions(newest.id()), drift_due);
  if (drift_due && checkDriftOffTheMap(view, checks)) return;
  spdlog::trace("reuse: keyframe {}: {} candidates (median depth {:.3f})", newest.id(),
                checks.size(), view.median_depth);
  ReuseEvent event;
  event.keyframe_id = newest.id();
  event.frame_index = newest_frame_index;
  event.timestamp = newest_timestamp;
  bringBack(view, checks, held, room, event);
  if (event.reactivated.empty()) return;
  if (settings_.reuse.trial_check) {
    confirmByTrial(event);
  } else {
    if (!settings_.localize_only)
      for (const int id : event.reactivated) store_.connect(newest.id(), id);
  }
  if (!event.reactivated.empty()) events_.reactivated(event);
}

bool MappingStage::canTake(int room, const std::vector<std::pair<int, int>>& held) const {
  return room > 0 || (!held.empty() && settings_.reuse.replace_ratio > 0.0);
}

bool MappingStage::driftCheckDue(int newest_id, bool can_take) const {
  const ReuseConfig& cfg = settings_.reuse;
  if (cfg.reanchor_min_keyframes <= 0 || !can_take) return false;
  // A map keyframe the window holds that still fits the newest keyframe as well as a candidate
  // must to come back (direct_min_inliers) keeps the window on the map: other map keyframes that
  // disagree with it by a few pixels measure the map's own inconsistency there (the seam of
  // an earlier lap's drift), and starting a new window at them trades one part of the map for
  // another (sim:loop2 0.0127 -> 0.0173 m when held keyframes fitting 96-100 % did not count).
  // One fitting worse may be sliding off with the window (a relocalisation's keyframe at 67 %
  // while two others put the window 10 px away).
  for (const Mapper::ReactivatedFit& f : mapper_.reactivatedFit())
    if (f.fitsAt(cfg.direct_min_inliers)) return false;
  // Only a window that was on the map a few keyframes ago: odometry does not drift by pixels in
  // a few keyframes, the window lost the map. The drift of a long way round is loop closure's
  // to spread over the way (a new window would leave it in the trajectory behind).
  return last_on_map_id_ >= 0 && newest_id - last_on_map_id_ <= cfg.reanchor_max_keyframes_off;
}

bool MappingStage::checkDriftOffTheMap(const ReuseView& view,
                                       const std::vector<ReuseCheck>& checks) {
  const ReuseConfig& cfg = settings_.reuse;
  std::vector<DriftCandidate> candidates;
  for (const ReuseCheck& c : checks) {
    // Every map keyframe the direct check found where it fits, within the basin or beyond.
    if (!(c.accepted || c.outside_basin) || !store_.inCurrentMap(c.id)) continue;
    const KeyframeRecord pose = store_.keyframe(c.id);
    if (pose.id < 0) continue;
    candidates.push_back({c.id, c.T_view_kf_aligned * pose.T_w_c.inverse(), c.in_view});
  }
  if (static_cast<int>(candidates.size()) < cfg.reanchor_min_keyframes) return false;
  // The scene the newest keyframe sees (a few hundred of the window's points), in the world.
  std::vector<Eigen::Vector3d> scene_w;
  const std::size_t step = depth_points_.size() / kDriftScenePoints + 1;
  const SE3d T_w_c = view.T_c_w.inverse();
  for (std::size_t i = 0; i < depth_points_.size(); i += step) {
    const DepthPoint& p = depth_points_[i];
    if (!(p.idepth > 0.f)) continue;
    scene_w.push_back(T_w_c * (view.camera.unproject(p.u, p.v).cast<double>() / p.idepth));
  }
  const DriftConsensus drift = findDriftConsensus(
      candidates, view.camera, scene_w, cfg.reanchor_agreement_px, cfg.reanchor_min_keyframes);
  if (!drift.found) return false;
  const double px = poseDistancePx(view.T_c_w, drift.T_c_w, view.camera, scene_w);
  // Near enough, the window optimisation pulls the window onto the map keyframes brought back.
  if (!(px > cfg.reanchor_min_drift_px)) return false;
  // Aligned again from where they put it, the agreeing keyframes must pass the direct check
  // there, basin included (they passed the others from the window's pose): the map is consistent
  // with itself at that place.
  ReuseView moved = view;
  moved.T_c_w = drift.T_c_w;
  int confirmed = 0;
  std::string unconfirmed;
  for (const int id : drift.agreeing) {
    const std::shared_ptr<const MarginalizedKeyframe> data = store_.keyframeData(id);
    const KeyframeRecord pose = store_.keyframe(id);
    if (!data || pose.id < 0) continue;
    ReuseCheck c;
    if (reuse_->checkDirect(moved, *data, pose, c))
      ++confirmed;
    else
      unconfirmed += "; keyframe " + std::to_string(id) + ": " + c.reason;
  }
  if (confirmed < cfg.reanchor_min_keyframes) {
    spdlog::debug(
        "reuse: keyframe {}: {} map keyframes put it {:.1f} px away, {} confirmed there{}",
        view.keyframe_id, drift.agreeing.size(), px, confirmed, unconfirmed);
    return false;
  }
  std::string held_fit;
  for (const Mapper::ReactivatedFit& f : mapper_.reactivatedFit())
    held_fit += fmt::format("; held keyframe {} fits {} of {}", f.id, f.inliers, f.residuals);
  spdlog::debug(
      "reuse: keyframe {}: the window drifted {:.1f} px off the map ({} map keyframes agree "
      "within {:.2f} px, {} confirmed{}): a new window from the map",
      view.keyframe_id, px, drift.agreeing.size(), drift.spread_px, confirmed, held_fit);
  ++reuse_stats_.window_reanchors;
  reanchor_.publish(ReanchorRequest{drift.id, view.T_c_w, drift.T_c_w});
  return true;
}

void MappingStage::takeBackMisfits() {
  // From a copy: deactivate() edits the list.
  const std::vector<Mapper::ReactivatedFit> fit = mapper_.reactivatedFit();
  for (const Mapper::ReactivatedFit& f : fit) {
    if (f.fitsAt(settings_.reuse.min_inlier_fraction)) continue;
    spdlog::debug("reuse: keyframe {} no longer fits ({} of {} residuals in the newest keyframe)",
                  f.id, f.inliers, f.residuals);
    takeOut(f.id);
  }
}

void MappingStage::takeOut(int id) {
  mapper_.deactivate(id);
  ++reuse_stats_.deactivations;
  if (resting_.takenOut(id, mapper_.newestKeyframe().id()))
    spdlog::debug("reuse: keyframe {} taken out again soon: it rests", id);
}

std::vector<std::pair<int, int>> MappingStage::replaceableReactivated() {
  // What each reactivated keyframe still contributes: its inlier residuals in the newest keyframe.
  // A corridor keeps old keyframes "fitting" long after the camera has moved on (their far points
  // stay in view), so a full window is not the end of the search: a candidate that sees clearly
  // more of the current view replaces the weakest one (bringBack).
  // Only a keyframe that has lost most of the view it was brought back for can be replaced: a
  // camera that stays in one place keeps its map keyframes (no churn).
  std::vector<std::pair<int, int>> held;  // (inliers, id), weakest first
  std::vector<std::pair<int, int>> peaks;
  for (const Mapper::ReactivatedFit& f : mapper_.reactivatedFit()) {
    int peak = f.inliers;
    for (const auto& [id, inliers] : reactivated_peak_)
      if (id == f.id) peak = std::max(peak, inliers);
    peaks.push_back({f.id, peak});
    if (2 * f.inliers < peak) held.push_back({f.inliers, f.id});
  }
  reactivated_peak_ = std::move(peaks);
  std::sort(held.begin(), held.end());
  return held;
}

ReuseView MappingStage::reuseView(const WindowKeyframe& newest) {
  // The newest keyframe as the search sees it: its corners with ORB descriptors.
  ReuseView view;
  view.keyframe_id = newest.id();
  view.T_c_w = newest.T_c_w;
  view.camera = mapper_.camera()[0];
  view.radial_k = mapper_.radialK();
  view.path_length = newest.path_length;
  view.chain_start_id = mapper_.chainStartId();
  view.pyramid = &newest.pyramid();
  view.pyramid_camera = &mapper_.camera();
  view.exposure = newest.exposure();
  view.aff = newest.aff;
  std::vector<Eigen::Vector2f> corners = mapper_.newestDescribableCorners();
  orb_->compute(newest.pyramid().gradients(0), corners, view.descriptors, orb_kept_);
  for (const std::uint32_t i : orb_kept_) view.corners.push_back(corners[i]);
  if (!settings_.localize_only) {  // (localising only, nothing that leaves is described)
    if (window_descriptions_.size() >= kMaxWindowDescriptions)
      window_descriptions_.erase(window_descriptions_.begin());
    window_descriptions_.push_back({newest.id(), std::move(corners), view.descriptors, orb_kept_});
  }
  mapper_.trackingPoints(depth_points_);
  if (!depth_points_.empty()) view.median_depth = medianDepth(depth_points_, idepths_);
  for (const KeyframeRecord& r : mapper_.windowPoses()) view.window_ids.push_back(r.id);
  return view;
}

std::vector<int> MappingStage::reuseExclusions(int newest_id) {
  // The map keyframes already in the window, and those taken out or turned down, while they rest.
  std::vector<int> exclude = mapper_.reactivatedIds();
  for (const int id : resting_.resting(newest_id)) exclude.push_back(id);
  return exclude;
}

void MappingStage::bringBack(const ReuseView& view, std::vector<ReuseCheck>& checks,
                             std::vector<std::pair<int, int>>& held, int room, ReuseEvent& event) {
  const bool can_take = canTake(room, held);
  int added = 0;
  for (ReuseCheck& c : checks) {
    ++reuse_stats_.candidates_checked;
    std::shared_ptr<const MarginalizedKeyframe> data;
    KeyframeRecord pose;
    const auto look_up = [&] {
      data = store_.keyframeData(c.id);
      pose = store_.keyframe(c.id);
      return data && pose.id >= 0;
    };
    if (c.direct_skipped) {
      if (!can_take || !look_up()) continue;
      reuse_->finishCheck(view, *data, pose, c);
    }
    if (!c.accepted) {
      ++(c.stage == ReuseStage::Direct     ? reuse_stats_.rejected_photometric
         : c.stage == ReuseStage::Features ? reuse_stats_.rejected_features
                                           : reuse_stats_.rejected_geometry);
      if (c.stage == ReuseStage::Direct)
        spdlog::debug("reuse: keyframe {} for {} rejected: {}", c.id, event.keyframe_id, c.reason);
      else
        spdlog::trace("reuse: keyframe {} for {} rejected: {}", c.id, event.keyframe_id, c.reason);
      continue;
    }
    if (!data && !look_up()) continue;
    if (added >= room) {
      // Replace the weakest reactivated keyframe when this one is expected to give clearly more
      // inliers (by default 4x in view, about twice the inliers: half the points in view are).
      if (held.empty() || !(settings_.reuse.replace_ratio > 0.0) ||
          !(c.in_view > settings_.reuse.replace_ratio * held.front().first))
        break;
      spdlog::debug("reuse: keyframe {} ({} inliers) makes room for keyframe {} ({} in view)",
                    held.front().second, held.front().first, c.id, c.in_view);
      takeOut(held.front().second);
      held.erase(held.begin());
      ++room;
    }
    mapper_.reactivate(*data, pose.T_w_c, pose.scale);
    ++reuse_stats_.reactivations;
    ++added;
    event.reactivated.push_back(c.id);
    spdlog::debug(
        "reuse: keyframe {} brought back for keyframe {} ({} points in view, {} %, {} "
        "ORB matches; direct: {:.0f} % fit, correlation {:.2f}, {:.2f} px)",
        c.id, event.keyframe_id, c.in_view, static_cast<int>(100 * c.overlap), c.matches,
        100 * c.direct_inliers, c.correlation, c.shift_px);
  }
}

void MappingStage::confirmByTrial(ReuseEvent& event) {
  // The direct check: a window optimisation with the new map keyframes, tried and undone. One
  // whose points do not fit the newest keyframe afterwards (the rule by which a reactivated
  // keyframe stays) never enters a real optimisation: a wrong one would pull the window towards
  // the wrong place before it could be taken out. Before any optimisation the share that fits says
  // little: the window has drifted from the map, and only the optimisation aligns it.
  const int newest_id = event.keyframe_id;
  const Mapper::ReactivationTrial trial = mapper_.tryReactivated();
  for (const Mapper::ReactivatedFit& f : trial.fits) {
    const auto it = std::find(event.reactivated.begin(), event.reactivated.end(), f.id);
    if (it == event.reactivated.end()) continue;  // reactivated earlier
    if (f.fitsAt(settings_.reuse.min_inlier_fraction)) {
      if (!settings_.localize_only) store_.connect(newest_id, f.id);
      continue;
    }
    spdlog::debug("reuse: keyframe {} for {} rejected by the trial: {} of {} residuals fit", f.id,
                  newest_id, f.inliers, f.residuals);
    mapper_.deactivate(f.id);
    event.reactivated.erase(it);
    --reuse_stats_.reactivations;
    ++reuse_stats_.rejected_photometric;
    resting_.rest(f.id, newest_id, settings_.reuse.trial_rest_keyframes);
  }
}

}  // namespace ldsm
