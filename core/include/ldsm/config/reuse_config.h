// The map reuse section of the configuration tree (ldsm/config.h).
#pragma once

#include "ldsm/config/range.h"

namespace ldsm {

/// Map reuse (DSM's local map covisibility window, with LDSM's neighbourhood search and feature
/// check; docs/map-reuse.md): when the camera comes back, map keyframes that see the current view
/// are brought back into the window (fixed), so revisits are tracked and optimised against the
/// existing map; new points are not selected where map points are seen, and keyframes that add
/// less than the map already had there are kept as poses only.
struct ReuseConfig {
  bool enabled = true;
  int max_reactivated = 3;  ///< map keyframes in the window at once
  /// With the window's map keyframes all taken, a candidate replaces the one that fits the newest
  /// keyframe worst when it has this many times more points in view than that one has inliers
  /// (0: never replace; a map keyframe stays until it no longer fits).
  double replace_ratio = 4.0;
  /// Keyframes made since a candidate left the window (a revisit, not the recent past).
  int min_keyframe_age = 10;
  /// A revisit: since the candidate the camera travelled this many times the straight-line
  /// distance between them, or it is closer than same_place_distance times the view's median
  /// depth (a camera panning back).
  double revisit_ratio = 3.0;
  double same_place_distance = 0.1;
  int search_hops = 8;               ///< covisibility-graph hops searched from the window
  double search_radius = 1.0;        ///< spatial search radius, times the view's median depth
  int max_candidates = 24;           ///< candidates checked per keyframe
  double min_overlap = 0.3;          ///< share of a candidate's points projecting into the view
  int min_points_in_view = 100;      ///< and at least this many
  double max_view_angle_deg = 60.0;  ///< between the candidate's and the view's optical axes
  /// ORB matches consistent with the projection. On vamr_desk_loop about two thirds of the ORB
  /// matches between revisiting keyframes are wrong (a repetitive desk) and land 50-400 px from
  /// the projection, the right ones within 0.2-6 px; a wrong match lands within
  /// feature_radius_px of the projection with a probability of ~0.07 % in a 640x480 image, so
  /// five consistent ones do not happen by chance (~1e-11 among 30 matches).
  int min_feature_matches = 5;
  double feature_radius_px = 8.0;  ///< how far a match may lie from the projected corner
  /// A reactivated keyframe stays while at least this share of its points' residuals in the
  /// newest keyframe are inliers.
  double min_inlier_fraction = 0.5;
  /// A map keyframe taken out of the window (it no longer fitted, or a better one replaced it)
  /// twice within this many keyframes is not searched again for as many keyframes: one that fits
  /// about as well as min_inlier_fraction may come back in the search that took it out (often
  /// rightly), but not come and go with every keyframe (docs/map-reuse.md, "Resting").
  int rest_keyframes = 5;
  /// Candidates that passed both checks are tried in a window optimisation that is undone: one
  /// whose points then fit the newest keyframe less than min_inlier_fraction is not brought
  /// back, and rests for trial_rest_keyframes keyframes. Off by default: it fixes the desk soak
  /// in deterministic mode, but its extra optimisation on the mapping thread costs the threaded
  /// real-time mode dropped frames (docs/map-reuse.md).
  bool trial_check = false;
  int trial_rest_keyframes = 5;
  /// The direct check, after the feature check: the candidate's points are aligned to the newest
  /// keyframe's image coarse to fine (from the relative pose the window and the map give), as
  /// the odometry measures. A candidate is brought back only when that alignment is good (at
  /// least direct_min_inliers of its points in view are inliers, their patterns correlate at
  /// least direct_min_correlation with the image) and lies in the window optimisation's basin:
  /// the window is optimised at full resolution only, so an alignment at full resolution alone,
  /// started from the window's pose, must reach the coarse-to-fine pose within direct_basin_px
  /// (mean shift of the points). A map keyframe further off does not fit after the optimisation
  /// and pulls the window towards a wrong place meanwhile (docs/map-reuse.md); how far the basin
  /// reaches depends on the texture (a few pixels on a fine-grained desk, more on smooth
  /// surfaces), hence the test rather than a fixed distance. direct_max_shift_px (0: none) bounds
  /// the distance itself. Costs one or two alignments of a few hundred points per candidate that
  /// passed the feature check.
  bool direct_check = true;
  double direct_min_inliers = 0.85;
  double direct_min_correlation = 0.7;
  double direct_basin_px = 1.0;
  double direct_max_shift_px = 0.0;
  /// Map keyframes that fit the newest keyframe but lie beyond the basin (the direct check) and
  /// agree within reanchor_agreement_px on where it is in the map: with at least
  /// reanchor_min_keyframes of them (and no map keyframe in the window that still fits the newest
  /// keyframe at direct_min_inliers), the window has drifted
  /// off the map beyond its reach, and tracking starts a new window from the map at the next frame
  /// (docs/map-reuse.md, "Re-anchoring a window that drifted off the map"; 0: never).
  int reanchor_min_keyframes = 2;
  double reanchor_agreement_px = 1.0;
  /// ... and put it at least this far from the window's pose (pixels, the mean shift of the scene;
  /// nearer, the window optimisation pulls the window onto them). On vamr_desk_loop map keyframes
  /// 6-8 px off passed the basin test, were brought back and no longer fitted after one
  /// optimisation (docs/map-reuse.md).
  double reanchor_min_drift_px = 4.0;
  /// ... and only when the window held a map keyframe (or started from one) at most this many
  /// keyframes before: the drift of a long way round is loop closure's to spread over the way.
  int reanchor_max_keyframes_off = 10;
  double coverage_radius_px = 3.0;  ///< no new point this close to a map point seen (0: off)
  /// The tracking reference holds at most this many times window.active_points points once
  /// map keyframes' points are in it: the map keyframes' points all (more than that: those
  /// alone), the window's own points thinned evenly to fill the rest (0: no limit). Without it,
  /// reactivated keyframes add about a quarter to the points every frame is tracked against
  /// (docs/map-reuse.md, "The tracking reference's budget").
  double reference_point_ratio = 1.0;
  /// A keyframe leaving the window keeps only its pose when a map keyframe of an earlier visit
  /// stands within redundancy_distance times its median depth, looks within
  /// redundancy_angle_deg the same way and sees redundancy_coverage of its points.
  bool cull_redundant = true;
  double redundancy_distance = 0.3;
  double redundancy_angle_deg = 30.0;
  double redundancy_coverage = 0.8;
  /// The map's budget: at most this many keyframes keep their points and features (0: no limit).
  /// Beyond it the most redundant one (the nearest to another kept keyframe looking the same
  /// way) keeps only its pose, so a long run in a large place stays within a fixed memory.
  int max_map_keyframes = 0;
  /// How a reactivated keyframe's pose is held: 0 fixed at the map's estimate (the default,
  /// docs/map-reuse.md), > 0 free with a prior of this weight per parameter.
  double reactivated_pose_weight = 0.0;
  /// The map keeps the points the window measured in at least this many other keyframes.
  int min_point_observations = 3;
  /// After tracking is lost, look for the camera in the map (relocalisation) for this long before
  /// a new map is started (0: start a new map at once).
  double relocalization_timeout_s = 5.0;
  int relocalization_min_inliers = 15;  ///< PnP inliers of a relocalisation
  /// Where no candidate's PnP pose holds, those with enough ORB matches whose PnP failed (most
  /// matches wrong: a repeated texture) are aligned directly from their own poses; the fit must
  /// pass the same checks, with a pattern correlation of 0.7 instead of 0.3.
  bool relocalization_direct_start = true;
  /// Before a new window is built on the map's answer (found away from the kept window, or in a
  /// loaded map), the map keyframes nearest to its pose other than the one it was found in are
  /// aligned from it; where at least one that holds ends elsewhere and no fewer end elsewhere than
  /// at the answer, the answer is refused (the frame stays lost and the next one is looked for).
  /// Only in the first half of relocalization_timeout_s after the loss (in localize-only mode too,
  /// which never gives up).
  bool relocalization_cross_check = true;
  /// Share of the keyframe's points in view that must be photometric inliers.
  double relocalization_min_direct_inliers = 0.5;
  /// Keyframes searched around the last known pose, times the last median depth.
  double relocalization_search_radius = 3.0;
  /// Of those, the nearest this many are tried for each frame while lost: each is matched (ORB),
  /// so this bounds the work per frame however dense the map is around the last pose.
  int relocalization_near_candidates = 24;
  /// Map keyframes anywhere in the map that look most like the lost frame (bag of words; needs
  /// loop closure's keyframe database) are tried too: a camera carried elsewhere while lost.
  int relocalization_place_candidates = 5;

  template <typename V>
  void visit(V& v) {
    v.field("enabled", enabled,
            "bring map keyframes that see the current view back into the window");
    v.field("max_reactivated", max_reactivated, Range<int>{1, 20},
            "map keyframes reactivated in the window at once");
    v.field("replace_ratio", replace_ratio, Range<double>{0.0, 1e6},
            "a candidate with this many times more points in view than the weakest reactivated "
            "keyframe has inliers replaces it (0: never)");
    v.field("min_keyframe_age", min_keyframe_age, Range<int>{1, 100000},
            "keyframes made since a reactivation candidate left the window");
    v.field("revisit_ratio", revisit_ratio, Range<double>{1.0, 1000.0},
            "a revisit travelled this many times the straight-line distance since the candidate");
    v.field("same_place_distance", same_place_distance, Range<double>{0.0, 10.0},
            "a candidate closer than this times the median depth is at the same place");
    v.field("search_hops", search_hops, Range<int>{0, 1000},
            "covisibility-graph hops searched from the window for candidates");
    v.field("search_radius", search_radius, Range<double>{0.0, 100.0},
            "spatial candidate search radius, times the newest keyframe's median depth");
    v.field("max_candidates", max_candidates, Range<int>{1, 1000},
            "reactivation candidates checked per keyframe");
    v.field("min_overlap", min_overlap, Range<double>{0.0, 1.0},
            "share of a candidate's points that must project into the current view");
    v.field("min_points_in_view", min_points_in_view, Range<int>{1, 100000},
            "candidate points that must project into the current view");
    v.field("max_view_angle_deg", max_view_angle_deg, Range<double>{0.0, 180.0},
            "largest angle between a candidate's and the current optical axis");
    v.field("min_feature_matches", min_feature_matches, Range<int>{0, 10000},
            "ORB matches consistent with the projection a candidate needs");
    v.field("feature_radius_px", feature_radius_px, Range<double>{0.5, 1000.0},
            "largest distance of a consistent match from the projected corner (pixels)");
    v.field("min_inlier_fraction", min_inlier_fraction, Range<double>{0.0, 1.0},
            "inlier share of a reactivated keyframe's residuals in the newest keyframe to stay");
    v.field("rest_keyframes", rest_keyframes, Range<int>{0, 1000},
            "keyframes within which a second take-out of a map keyframe makes it rest as long");
    v.field("trial_check", trial_check,
            "try new map keyframes in an undone window optimisation before bringing them back");
    v.field("trial_rest_keyframes", trial_rest_keyframes, Range<int>{0, 1000},
            "keyframes a candidate turned down by the trial is not searched again");
    v.field("direct_check", direct_check,
            "align a candidate's points to the newest keyframe before bringing it back");
    v.field("direct_min_inliers", direct_min_inliers, Range<double>{0.0, 1.0},
            "share of a candidate's points in view that must be inliers of the alignment");
    v.field("direct_min_correlation", direct_min_correlation, Range<double>{-1.0, 1.0},
            "mean pattern correlation of the aligned points with the newest keyframe");
    v.field("direct_basin_px", direct_basin_px, Range<double>{0.0, 1000.0},
            "a full-resolution alignment from the window's pose must reach the coarse-to-fine "
            "one within this (pixels; 0: not tested)");
    v.field("direct_max_shift_px", direct_max_shift_px, Range<double>{0.0, 1000.0},
            "largest mean shift of the candidate's points between the window's pose and the "
            "aligned one (pixels; 0: no limit)");
    v.field("reanchor_min_keyframes", reanchor_min_keyframes, Range<int>{0, 1000},
            "map keyframes beyond the basin that must agree before the window is started again "
            "from the map (0: never)");
    v.field("reanchor_min_drift_px", reanchor_min_drift_px, Range<double>{0.0, 1000.0},
            "how far from the window's pose they must put the newest keyframe (pixels)");
    v.field("reanchor_max_keyframes_off", reanchor_max_keyframes_off, Range<int>{0, 100000},
            "keyframes since the window last held a map keyframe within which it may be "
            "started again from the map");
    v.field(
        "reanchor_agreement_px", reanchor_agreement_px, Range<double>{0.0, 1000.0},
        "how closely (mean shift of the scene, pixels) they must agree on the newest keyframe's "
        "pose");
    v.field("coverage_radius_px", coverage_radius_px, Range<double>{0.0, 50.0},
            "no new point this close to a map point seen in the keyframe (0: off)");
    v.field("reference_point_ratio", reference_point_ratio, Range<double>{0.0, 100.0},
            "most tracking reference points, times window.active_points, once map keyframes' "
            "points are in it: those all stay, the window's own are thinned (0: no limit)");
    v.field("cull_redundant", cull_redundant,
            "keep only the pose of keyframes an earlier map keyframe already covers");
    v.field("max_map_keyframes", max_map_keyframes, Range<int>{0, 10000000},
            "keyframes that keep points and features at most; beyond, the most redundant keeps "
            "only its pose (0: no limit)");
    v.field("redundancy_distance", redundancy_distance, Range<double>{0.0, 10.0},
            "a covering map keyframe stands within this times the keyframe's median depth");
    v.field("redundancy_angle_deg", redundancy_angle_deg, Range<double>{0.0, 180.0},
            "and looks within this angle the same way");
    v.field("redundancy_coverage", redundancy_coverage, Range<double>{0.0, 1.0},
            "and sees this share of the keyframe's points");
    v.field("reactivated_pose_weight", reactivated_pose_weight, Range<double>{0.0, 1e12},
            "0: reactivated keyframes fixed; > 0: free with a prior of this weight");
    v.field("min_point_observations", min_point_observations, Range<int>{1, 100},
            "the map keeps points measured in at least this many other keyframes");
    v.field("relocalization_timeout_s", relocalization_timeout_s, Range<double>{0.0, 1e6},
            "seconds of relocalisation attempts after a tracking loss before a new map starts");
    v.field("relocalization_min_inliers", relocalization_min_inliers, Range<int>{6, 10000},
            "PnP inliers a relocalisation needs");
    v.field("relocalization_direct_start", relocalization_direct_start,
            "a candidate whose PnP fails is aligned directly from its own pose");
    v.field("relocalization_cross_check", relocalization_cross_check,
            "the map's answer is checked against its neighbouring keyframes before a new window");
    v.field("relocalization_min_direct_inliers", relocalization_min_direct_inliers,
            Range<double>{0.0, 1.0},
            "share of the keyframe's points in view that must be photometric inliers");
    v.field("relocalization_search_radius", relocalization_search_radius,
            Range<double>{0.0, 1000.0},
            "keyframes searched around the last known pose, times the last median depth");
    v.field("relocalization_near_candidates", relocalization_near_candidates, Range<int>{1, 10000},
            "nearest keyframes to the last known pose tried per lost frame");
    v.field("relocalization_place_candidates", relocalization_place_candidates, Range<int>{0, 100},
            "map keyframes that look most like a lost frame (bag of words) tried anywhere in the "
            "map (0: only near the last pose)");
  }
};

}  // namespace ldsm
