// The loop closure section of the configuration tree (ldsm/config.h).
#pragma once

#include "ldsm/config/range.h"

namespace ldsm {

/// Loop closure: place recognition over keyframes that left the window, Sim(3) verification and
/// pose-graph correction in a low-priority background task (inline in deterministic mode).
struct LoopConfig {
  bool enabled = true;
  /// Keyframes right before the query that are never loop candidates (the recent neighbourhood).
  int exclude_recent_keyframes = 20;
  int max_candidates = 3;  ///< best BoW candidates verified per keyframe
  int min_inliers = 20;    ///< inliers of the Sim(3) after refinement to accept a loop
  /// ORB matches between the query and a candidate before any geometry is tried, and the PnP
  /// RANSAC inliers needed (also the matches whose candidate feature has a depth, which PnP uses).
  int min_matches = 30;
  int min_pnp_inliers = 20;
  /// Corners described (ORB) on a keyframe leaving the window, besides the odometry's own, and
  /// the weakest Shi-Tomasi score they may have (9: a gradient of 3 grey levels per pixel).
  int corners_per_keyframe = 400;
  double corner_min_score = 9.0;
  /// The odometry's drift model: the uncertainty the window's relative poses accumulate along the
  /// chain of keyframes. Per keyframe step a random walk of rotation_drift (radians) and
  /// scale_drift (log scale), and translation_drift times the distance travelled. It weighs the
  /// odometry edges of the pose graph against the loops' own measured uncertainty, and says how
  /// far a loop may disagree with the trajectory before that is drift rather than noise.
  double odometry_rotation_drift = 5e-4;
  double odometry_scale_drift = 2e-3;
  double odometry_translation_drift = 0.01;
  /// A verified loop corrects the trajectory only when its measured Sim(3) disagrees with the
  /// current estimate by more than this squared Mahalanobis distance under the loop's covariance
  /// plus the drift the odometry chain between the two keyframes may have accumulated (7 DoF;
  /// 18.48 = chi-square 99 %). Smaller disagreement is within the accuracy of both.
  double correction_chi2 = 18.48;
  /// LDSM's deferred pose graph: after a constraint that shows significant drift (a loop, or a
  /// map keyframe brought back into the window), the pose graph is optimised once no new such
  /// constraint arrived for pose_graph_delay_keyframes keyframes (all of them in one solve), and
  /// at the latest pose_graph_max_delay_keyframes after the first one (or at the end of a run).
  int pose_graph_delay_keyframes = 5;
  int pose_graph_max_delay_keyframes = 20;
  /// Keyframes without data in the map (culled as redundant, or dropped for the map's budget)
  /// leave the pose graph once this many keyframes were processed after them: each is folded
  /// into the neighbour it is most firmly tied to (its edges rerouted there), so that the graph
  /// grows with the map, not with time. The recent trajectory stays in the graph in full, for
  /// the corrections that spread drift over it.
  int pose_graph_recent_keyframes = 100;
  /// LDSM: candidates that share more than this many points with the query keyframe (through the
  /// window, or through map keyframes brought back into it) are no loops: they are connected
  /// already.
  int covisible_shared_points = 100;
  /// Map keyframes brought back into the window (map reuse) give the pose graph relative-pose
  /// constraints from the window optimisation, so that the drift a revisit reveals is spread
  /// over the keyframes in between.
  bool reuse_constraints = true;
  /// A correction holds the map keyframes the window holds (map reuse) where they are, together
  /// with the newest keyframe: the window's photometric optimisation measured how they lie to it,
  /// far more precisely than any pose-graph edge, and a correction that moved them would leave
  /// the window holding map points that no longer fit its images. The rest of the map moves.
  bool hold_reused_keyframes = true;
  /// Keyframes waiting for loop closure (threaded mode; rounded up to a power of two). A
  /// keyframe that finds the queue full is not indexed (loop closure never holds up mapping).
  int queue_capacity = 16;
  /// At the end of a run (and before a map is saved) loop closure gets this long to process its
  /// queue and the pending pose graph (threaded mode; plus the time a running job takes to
  /// notice the abort); then it is stopped for the rest of the session and what is unfinished
  /// is reported. 0 abandons even the final pose-graph run.
  double finish_timeout_s = 60.0;

  template <typename V>
  void visit(V& v) {
    v.field("enabled", enabled, "detect and close loops");
    v.field("exclude_recent_keyframes", exclude_recent_keyframes, Range<int>{1, 10000},
            "recent keyframes that are never loop candidates");
    v.field("max_candidates", max_candidates, Range<int>{1, 20},
            "bag-of-words candidates verified per keyframe");
    v.field("min_inliers", min_inliers, Range<int>{10, 1000},
            "Sim(3) inliers needed to accept a loop");
    v.field("min_matches", min_matches, Range<int>{8, 10000},
            "ORB matches with a candidate needed before its geometry is tried");
    v.field("min_pnp_inliers", min_pnp_inliers, Range<int>{10, 1000},
            "PnP RANSAC inliers needed (and candidate matches with a depth)");
    v.field("corners_per_keyframe", corners_per_keyframe, Range<int>{0, 5000},
            "extra corners described (ORB) on each keyframe leaving the window");
    v.field("corner_min_score", corner_min_score, Range<double>{0.0, 1e6},
            "weakest Shi-Tomasi score of those corners");
    v.field("odometry_rotation_drift", odometry_rotation_drift, Range<double>{1e-6, 0.1},
            "odometry drift model: rotation random walk per keyframe (radians)");
    v.field("odometry_scale_drift", odometry_scale_drift, Range<double>{1e-6, 0.5},
            "odometry drift model: log-scale random walk per keyframe");
    v.field("odometry_translation_drift", odometry_translation_drift, Range<double>{1e-5, 1.0},
            "odometry drift model: translation error per distance travelled");
    v.field("correction_chi2", correction_chi2, Range<double>{0.0, 1e9},
            "squared Mahalanobis distance (7 DoF) of the loop's disagreement with the estimate, "
            "under the loop's and the odometry chain's uncertainty, above which the pose graph "
            "corrects the trajectory; 0 corrects every loop");
    v.field("pose_graph_delay_keyframes", pose_graph_delay_keyframes, Range<int>{0, 1000},
            "keyframes without a new significant constraint before the pose graph is optimised");
    v.field("pose_graph_max_delay_keyframes", pose_graph_max_delay_keyframes, Range<int>{0, 100000},
            "keyframes after the first significant constraint by which the pose graph is "
            "optimised at the latest");
    v.field("pose_graph_recent_keyframes", pose_graph_recent_keyframes, Range<int>{0, 10000000},
            "keyframes processed after a keyframe without map data before it is folded out of "
            "the pose graph into its most firmly tied neighbour");
    v.field("covisible_shared_points", covisible_shared_points, Range<int>{0, 100000},
            "points a candidate may share with the query keyframe before it counts as connected "
            "(no loop)");
    v.field("reuse_constraints", reuse_constraints,
            "map keyframes brought back into the window constrain the pose graph");
    v.field("hold_reused_keyframes", hold_reused_keyframes,
            "a correction keeps the map keyframes held in the window where they are");
    v.field("queue_capacity", queue_capacity, Range<int>{1, 1024},
            "keyframes waiting for loop closure (threaded mode); one that finds the queue full "
            "is not indexed");
    v.field("finish_timeout_s", finish_timeout_s, Range<double>{0.0, 86400.0},
            "seconds loop closure may take at the end of a run to process its queue and the "
            "pending pose graph before it is stopped");
  }
};

}  // namespace ldsm
