// Configuration: a tree of plain structs with defaults. Every struct lists its fields once, in
// visit(), with key, allowed range and help text; validation, YAML loading and printing of the
// defaults are all driven from that single list (see config_visitors.h), so a field can never be
// documented in one place and forgotten in another.
#pragma once

#include <string>
#include <vector>

namespace ldsm {

/// Inclusive range of allowed values of a numeric field.
template <typename T>
struct Range {
  T min;
  T max;
};

struct SystemConfig {
  /// One thread, every stage in order: identical output for identical input.
  bool deterministic = false;
  /// Live input (camera, real-time replay): when tracking falls behind, the oldest queued frame
  /// is dropped and counted. Off (offline): submit() waits for room and nothing is dropped.
  bool live = false;
  /// Frame buffers preallocated at start-up for the threaded pipeline. The tracking queue holds
  /// the largest power of two <= frame_pool_size - 2 frames (one buffer is being filled, one
  /// tracked).
  int frame_pool_size = 6;
  /// CPU the tracking thread is pinned to (-1: any).
  int tracking_cpu = -1;
  /// CPU the mapping thread is pinned to (-1: any).
  int mapping_cpu = -1;
  /// Tracked frames the mapping queue holds (threaded mode): how far tracking may run ahead of
  /// mapping before it waits.
  int mapping_queue = 4;
  /// Frame poses kept in memory (System::trajectory()); older ones are handed out by
  /// System::takeRetiredFrames() with the poses they had then (later loop corrections no longer
  /// move them), so that memory does not grow with the length of a run. 0: every frame.
  /// -1 (automatic): every frame offline, kLiveFrameHistory frames when `live`.
  int frame_history = -1;
  static constexpr int kLiveFrameHistory = 9000;  ///< 5 minutes at 30 Hz
  /// Threads for data-parallel work inside a stage, the stage's own thread included: the
  /// initializer's motion hypotheses (tracking stage, while the mapping thread is idle), the
  /// tracing and the window optimisation's linearisation (mapping stage). The work is split into
  /// independent tasks combined in a fixed order, so the results do not depend on it.
  /// 0 (automatic): 1 in deterministic mode; else the cores available for the tracking stage and
  /// the cores but one for the mapping stage (tracking keeps its own), each at most
  /// kMaxAutomaticParallelThreads.
  int parallel_threads = 0;
  static constexpr int kMaxAutomaticParallelThreads = 4;

  /// The number of frames frame_history keeps (0: every one).
  int frameHistory() const {
    return frame_history >= 0 ? frame_history : live ? kLiveFrameHistory : 0;
  }

  template <typename V>
  void visit(V& v) {
    v.field("deterministic", deterministic,
            "run every stage on one thread in order (bit-identical results)");
    v.field("live", live,
            "live input: drop the oldest queued frame when tracking falls behind (off: wait)");
    v.field("frame_pool_size", frame_pool_size, Range<int>{4, 1024},
            "frame buffers allocated at start-up; the tracking queue holds the largest power of "
            "two <= frame_pool_size - 2");
    v.field("tracking_cpu", tracking_cpu, Range<int>{-1, 1023},
            "CPU to pin the tracking thread to (-1: any)");
    v.field("mapping_cpu", mapping_cpu, Range<int>{-1, 1023},
            "CPU to pin the mapping thread to (-1: any)");
    v.field("mapping_queue", mapping_queue, Range<int>{1, 64},
            "tracked frames the mapping queue holds before tracking waits (threaded mode)");
    v.field("frame_history", frame_history, Range<int>{-1, 1000000000},
            "frame poses kept in memory; older ones go to System::takeRetiredFrames() (0: every "
            "frame, -1: every frame offline, 9000 when live)");
    v.field("parallel_threads", parallel_threads, Range<int>{0, 64},
            "threads for data-parallel work inside a stage, its own included (0: 1 when "
            "deterministic, else the cores, but one for mapping, at most 4); results do not "
            "depend on it");
  }
};

struct PhotometricConfig {
  bool use_response = true;  ///< undo the inverse response G^-1 when pcalib.txt is given
  bool use_vignette = true;  ///< divide by the vignette V(x) when vignette.png is given
  bool use_exposure = true;  ///< use exposure times when the source provides them
  /// Weight of the prior keeping affine brightness (a, b) near zero when exposures are unknown.
  double affine_prior_weight_unknown = 1e-3;
  /// Weight of that prior when the photometric calibration and exposures are known.
  double affine_prior_weight_known = 1e6;
  /// Raw pixel value (0-255, before any correction) from which a pixel counts as saturated. A
  /// clipped pixel does not follow the brightness model: when the exposure changes the clipped
  /// area's border moves. 256 turns the check off.
  double clipped_level = 250.0;

  template <typename V>
  void visit(V& v) {
    v.field("use_response", use_response, "undo the camera response when pcalib.txt is given");
    v.field("use_vignette", use_vignette, "correct the vignette when vignette.png is given");
    v.field("use_exposure", use_exposure, "use exposure times when the source provides them");
    v.field("affine_prior_weight_unknown", affine_prior_weight_unknown, Range<double>{0.0, 1e12},
            "prior weight on affine brightness (a, b) when exposures are unknown");
    v.field("affine_prior_weight_known", affine_prior_weight_known, Range<double>{0.0, 1e12},
            "prior weight on affine brightness (a, b) with full photometric calibration");
    v.field("clipped_level", clipped_level, Range<double>{1.0, 256.0},
            "raw pixel value from which a pixel counts as saturated (256: off)");
  }
};

struct PointSelectionConfig {
  int points_per_keyframe = 2000;  ///< target number of selected pixels per keyframe
  double corner_fraction = 0.15;   ///< share of those that are Shi-Tomasi corners (features)
  int grid_block_size = 32;        ///< adaptive threshold grid cell, pixels
  double min_gradient = 7.0;       ///< constant added to the regional gradient threshold
  /// No point is selected within this many pixels (Chebyshev) of a saturated pixel (see
  /// photometric.clipped_level): 2 is the reach of the residual pattern.
  int clipped_margin = 2;

  template <typename V>
  void visit(V& v) {
    v.field("points_per_keyframe", points_per_keyframe, Range<int>{100, 20000},
            "target number of points selected per keyframe");
    v.field("corner_fraction", corner_fraction, Range<double>{0.0, 1.0},
            "share of selected points that are Shi-Tomasi corners (carry ORB descriptors)");
    v.field("grid_block_size", grid_block_size, Range<int>{8, 128},
            "cell size in pixels of the adaptive gradient-threshold grid");
    v.field("min_gradient", min_gradient, Range<double>{0.0, 255.0},
            "constant added to the regional gradient threshold");
    v.field("clipped_margin", clipped_margin, Range<int>{0, 32},
            "pixels kept between a selected point and a saturated pixel");
  }
};

struct TrackingConfig {
  int pyramid_levels = 5;  ///< pyramid levels used by the coarse tracker
  int max_iterations_per_level = 10;
  double huber_threshold = 9.0;  ///< Huber threshold of the photometric residual, grey levels
  /// A frame whose residual grows past this many times the last frame's while fewer than half of
  /// its points are inliers is not this scene (a glitch, noise, a covered lens): tracking is lost
  /// there rather than accepting a garbage pose. 0 disables the check.
  double max_rmse_growth = 5.0;

  template <typename V>
  void visit(V& v) {
    v.field("pyramid_levels", pyramid_levels, Range<int>{1, 8},
            "image pyramid levels for coarse-to-fine tracking");
    v.field("max_iterations_per_level", max_iterations_per_level, Range<int>{1, 100},
            "Gauss-Newton iterations per pyramid level");
    v.field("huber_threshold", huber_threshold, Range<double>{0.1, 255.0},
            "Huber threshold of photometric residuals (grey levels)");
    v.field("max_rmse_growth", max_rmse_growth, Range<double>{0.0, 1e6},
            "a frame with this many times the last residual and < 50 % inliers is lost (0: off)");
  }
};

struct WindowConfig {
  int min_keyframes = 5;     ///< keyframes kept before marginalisation starts
  int max_keyframes = 7;     ///< hard upper bound of the optimisation window
  int active_points = 2000;  ///< target number of active points in the whole window
  int max_iterations = 6;    ///< Levenberg-Marquardt iterations per new keyframe
  /// The iterations stop once a step changes the window energy by less than this fraction
  /// (either way): past it, steps only move points at the noise floor of the residuals.
  double min_relative_decrease = 3e-4;
  double outlier_threshold = 12.0;  ///< RMS pattern residual (grey levels) of an outlier
  /// Each keyframe's outlier threshold follows its own residual level after its first
  /// optimisation (DSO's rule); outlier_threshold then only applies before that and to the
  /// immature points' depth search.
  bool adaptive_outlier_threshold = true;
  double min_trace_quality = 3.0;   ///< immature point: second-best / best match energy
  double max_trace_interval = 8.0;  ///< immature point: depth interval in pixels to activate

  template <typename V>
  void visit(V& v) {
    v.field("min_keyframes", min_keyframes, Range<int>{2, 20},
            "keyframes in the window before old ones are marginalised");
    v.field("max_keyframes", max_keyframes, Range<int>{3, 20},
            "maximum keyframes in the optimisation window");
    v.field("active_points", active_points, Range<int>{100, 50000},
            "target number of active points in the window");
    v.field("max_iterations", max_iterations, Range<int>{1, 50},
            "Levenberg-Marquardt iterations of the window per new keyframe");
    v.field("min_relative_decrease", min_relative_decrease, Range<double>{0.0, 1.0},
            "the window iterations stop once a step changes the energy by less than this "
            "fraction");
    v.field("outlier_threshold", outlier_threshold, Range<double>{1.0, 255.0},
            "RMS pattern residual (grey levels) above which a residual is an outlier");
    v.field("adaptive_outlier_threshold", adaptive_outlier_threshold,
            "adapt each keyframe's outlier threshold to its residual level");
    v.field("min_trace_quality", min_trace_quality, Range<double>{1.0, 100.0},
            "second-best / best match energy an immature point needs to be activated");
    v.field("max_trace_interval", max_trace_interval, Range<double>{0.5, 100.0},
            "largest depth uncertainty (pixels along the epipolar line) to activate a point");
  }
};

struct KeyframeConfig {
  /// Weight of the RMS optical flow from translation alone, per pixel of (width + height)/1120.
  /// DSO's 0.04 and 0.02 below made a keyframe of 167 of kitti00_200's 200 frames; 0.65 times
  /// them, with DSO's rate while the camera is being corrected (settling_flow_scale), made 126
  /// and cost 19 % fewer instructions at a lower ATE on both real sequences (every sequence's
  /// figures: docs/engine.md, "Keyframe rate").
  double flow_translation_weight = 0.026;
  /// Weight of the RMS optical flow of the full motion (rotation and translation).
  double flow_full_weight = 0.013;
  /// Both flow weights are multiplied by this while the calibration refinement is still
  /// correcting the camera (CalibrationRefinement::settling(): before its first window, and while
  /// an applied parameter moved by more than half its dead band over the last three windows):
  /// each window is one measurement of the camera, and frames tracked with a camera still being
  /// corrected bend the trajectory.
  double settling_flow_scale = 1.5;
  double brightness_weight = 2.0;  ///< weight of |log brightness change|
  /// A keyframe is made when the tracking RMSE exceeds this times the RMSE of the first frame
  /// tracked against the current reference.
  double residual_factor = 2.0;
  /// A keyframe is made when the reference's points cover less than this share of the image
  /// cells they covered in the reference (CoarseTrackingResult::coverage; 0: never). The flow
  /// terms miss a camera that backs away: its reference's points are the far ones, they flow
  /// little, while the near scene entering at the borders has no points yet.
  double min_coverage = 0.9;

  template <typename V>
  void visit(V& v) {
    v.field("flow_translation_weight", flow_translation_weight, Range<double>{0.0, 10.0},
            "keyframe score weight of the translational optical flow");
    v.field("flow_full_weight", flow_full_weight, Range<double>{0.0, 10.0},
            "keyframe score weight of the full (rotation + translation) optical flow");
    v.field("settling_flow_scale", settling_flow_scale, Range<double>{0.1, 10.0},
            "both flow weights times this while the calibration refinement is still correcting "
            "the camera");
    v.field("brightness_weight", brightness_weight, Range<double>{0.0, 100.0},
            "keyframe score weight of |log brightness change|");
    v.field("residual_factor", residual_factor, Range<double>{1.0, 100.0},
            "new keyframe when the tracking RMSE grows by this factor");
    v.field("min_coverage", min_coverage, Range<double>{0.0, 1.0},
            "new keyframe when the reference's points cover less than this share of the image "
            "cells they covered in the reference");
  }
};

struct InitializerConfig {
  /// RMS optical flow (pixels) caused by the translation that counts as real parallax.
  double min_parallax_px = 6.0;
  /// Part of that flow (RMS, pixels) that no rotation may explain.
  double min_rotation_free_parallax_px = 1.5;
  int confirm_frames = 5;      ///< frames the parallax must hold before the map is accepted
  double point_density = 2.0;  ///< initializer points per points.points_per_keyframe
  /// Motion hypotheses tracked from the reference (at rest, small +-x, +-y, +-z translations);
  /// the one with the lowest photometric error wins. 1: start at rest only.
  int hypotheses = 7;

  template <typename V>
  void visit(V& v) {
    v.field("min_parallax_px", min_parallax_px, Range<double>{0.5, 100.0},
            "RMS optical flow (pixels) from the translation needed to initialise");
    v.field("min_rotation_free_parallax_px", min_rotation_free_parallax_px,
            Range<double>{0.0, 100.0},
            "part of that flow (RMS pixels) that a rotation cannot explain; at most "
            "min_parallax_px");
    v.field("confirm_frames", confirm_frames, Range<int>{0, 100},
            "frames the parallax must hold before the initial map is accepted");
    v.field("point_density", point_density, Range<double>{0.1, 20.0},
            "points of the initializer's reference, per points.points_per_keyframe");
    v.field("hypotheses", hypotheses, Range<int>{1, 7},
            "motion hypotheses tracked during initialisation (at rest, +-x, +-y, +-z); the one "
            "with the lowest photometric error wins");
  }
};

/// The whole configuration tree. Sections are added here as modules arrive.
/// Loop closure: place recognition over keyframes that left the window, Sim(3) verification and
/// pose-graph correction in a low-priority background task (inline in deterministic mode).
struct LoopConfig {
  bool enabled = true;
  /// Keyframes right before the query that are never loop candidates (the recent neighbourhood).
  int exclude_recent_keyframes = 20;
  int max_candidates = 3;  ///< best BoW candidates verified per keyframe
  int min_inliers = 20;    ///< inliers of the Sim(3) after refinement to accept a loop
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

  template <typename V>
  void visit(V& v) {
    v.field("enabled", enabled, "detect and close loops");
    v.field("exclude_recent_keyframes", exclude_recent_keyframes, Range<int>{1, 10000},
            "recent keyframes that are never loop candidates");
    v.field("max_candidates", max_candidates, Range<int>{1, 20},
            "bag-of-words candidates verified per keyframe");
    v.field("min_inliers", min_inliers, Range<int>{10, 1000},
            "Sim(3) inliers needed to accept a loop");
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
  }
};

/// Online refinement of the camera calibration. Rectified images that still carry a little radial
/// distortion (a calibration fitted on other data, a lens that moved) bend every ray by a few
/// pixels towards the image border; the photometric error then drives rotation and scale wrong
/// (kitti00_200 with its given calibration: 1.07 m ATE, 0.29 m with k1 = 0.02). A wrong focal
/// length or principal point does the same. The window estimates a correction of the radial
/// distortion k, the focal length and the principal point together (backend/
/// calibration_refinement.h); each part is applied once its estimate leaves its dead band.
struct CalibrationRefinementConfig {
  /// Estimate a residual radial distortion k (x_image = x (1 + k |x|^2) in the output camera's
  /// normalized coordinates) from the window's photometric error and apply it in the window.
  bool refine_radial = true;
  /// Estimate a common scale of the focal lengths (fx, fy) and apply it. With the focal scale
  /// free the radial estimate no longer absorbs a focal error; the significance test keeps a
  /// forward drive's bias from being applied. kitti00_200 with the five camera.txt variants of
  /// docs/engine.md: worst ATE 0.45 -> 0.31 m; `--fov` also turns it on.
  bool refine_focal = true;
  /// Estimate a shift of the principal point (cx, cy) and apply it. Off by default: a shift is
  /// almost a rotation of every keyframe, so windows see little of it.
  bool refine_principal_point = false;
  /// Weight kept by older keyframes' estimates per new keyframe (1: never forget).
  double memory = 0.95;
  /// The radial correction is applied only once the estimate exceeds this (and dropped again
  /// below half of it): a small correction costs more consistency in the window than it gains.
  double radial_dead_band = 0.003;
  /// Largest correction |k| ever applied.
  double radial_max = 0.1;
  /// The focal correction (relative, log scale) is applied once it exceeds this.
  double focal_dead_band = 0.005;
  /// Largest relative focal correction.
  double focal_max = 0.3;
  /// The principal point correction (pixels of the full-resolution rectified image, each axis)
  /// is applied once it exceeds this.
  double principal_point_dead_band = 1.5;
  /// Largest principal point correction (pixels, each axis).
  double principal_point_max = 60.0;
  /// The first windows' estimates scatter more (the window still holds the initialisation's
  /// short baselines): after n windows a correction is applied only once its estimate exceeds
  /// its dead band times (1 + settle_windows / n). Measured on the rendered loop started 3 or 15
  /// frames in, exactly calibrated, every part refined: with 0, estimates of 1.1-1.4 dead bands
  /// in windows 1-12 were applied and the ATE was 2-3x the unrefined run's (docs/engine.md).
  double settle_windows = 3.0;
  /// A correction is applied only once its estimate is this many realistic standard deviations
  /// from 0 (0: no such test; CalibrationRefinement::realisticSigma). The realistic deviation is
  /// the fused curvature's (formal) one, scaled by how far the windows' estimates scatter around
  /// the fused estimate in units of their own formal deviations, and by the keyframes a window
  /// shares with the next (each keyframe's residuals enter that many windows). The formal
  /// deviations alone are 10-60x too small: on a rendered forward corridor, exactly calibrated,
  /// focal and radial estimates 15 formal deviations from 0 were a bias of the scene, not an
  /// error of the camera (docs/engine.md).
  double radial_significance = 2.0;
  double focal_significance = 2.0;
  /// Off for the principal point: its windows' estimates lag a 10 px error for tens of windows,
  /// which the scatter counts, and the test held its correction back until the trajectory had
  /// doubled its error (SelfCalibration.FindsAPrincipalPointTenPixelsOff: ATE 0.0105 -> 0.0234 m).
  double principal_point_significance = 0.0;

  template <typename V>
  void visit(V& v) {
    v.field("refine_radial", refine_radial,
            "estimate and apply a residual radial distortion of the rectified images");
    v.field("refine_focal", refine_focal,
            "estimate and apply a common correction of the focal lengths");
    v.field("refine_principal_point", refine_principal_point,
            "estimate and apply a correction of the principal point");
    v.field("memory", memory, Range<double>{0.5, 1.0},
            "weight kept by older keyframes' calibration estimates per new keyframe");
    v.field("radial_dead_band", radial_dead_band, Range<double>{0.0, 0.1},
            "radial correction applied only once its estimate exceeds this");
    v.field("radial_max", radial_max, Range<double>{0.001, 0.5},
            "largest radial correction |k| applied");
    v.field("focal_dead_band", focal_dead_band, Range<double>{0.0, 0.1},
            "focal correction (relative) applied only once its estimate exceeds this");
    v.field("focal_max", focal_max, Range<double>{0.001, 0.7},
            "largest relative focal correction applied");
    v.field("principal_point_dead_band", principal_point_dead_band, Range<double>{0.0, 50.0},
            "principal point correction (pixels) applied only once its estimate exceeds this");
    v.field("principal_point_max", principal_point_max, Range<double>{0.1, 500.0},
            "largest principal point correction (pixels, each axis) applied");
    v.field("settle_windows", settle_windows, Range<double>{0.0, 100.0},
            "after n windows a correction needs its dead band times (1 + this / n) to be applied");
    v.field("radial_significance", radial_significance, Range<double>{0.0, 10.0},
            "radial correction applied only once its estimate is this many realistic standard "
            "deviations from 0 (0: no such test)");
    v.field("focal_significance", focal_significance, Range<double>{0.0, 10.0},
            "focal correction applied only once its estimate is this many realistic standard "
            "deviations from 0 (0: no such test)");
    v.field("principal_point_significance", principal_point_significance, Range<double>{0.0, 10.0},
            "principal point correction applied only once its estimate is this many realistic "
            "standard deviations from 0 (0: no such test)");
  }
};

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

/// Maps across sessions (docs/map-file.md): how a loaded map is used.
struct MapConfig {
  /// Localise in a loaded map without changing it: keyframes that leave the window are dropped,
  /// loop closure adds nothing, no new map is started (the camera stays lost until it is found
  /// in the map), so memory stays flat however long it runs. Needs a loaded map.
  bool localize_only = false;

  template <typename V>
  void visit(V& v) {
    v.field("localize_only", localize_only,
            "localise in the loaded map without changing it (needs a loaded map)");
  }
};

struct Config {
  SystemConfig system;
  PhotometricConfig photometric;
  PointSelectionConfig points;
  TrackingConfig tracking;
  WindowConfig window;
  KeyframeConfig keyframes;
  InitializerConfig initializer;
  LoopConfig loop;
  CalibrationRefinementConfig calibration;
  ReuseConfig reuse;
  MapConfig map;

  template <typename V>
  void visit(V& v) {
    v.section("system", system, "threads and determinism");
    v.section("photometric", photometric, "photometric calibration and exposure handling");
    v.section("points", points, "point selection");
    v.section("tracking", tracking, "coarse tracking of every frame");
    v.section("window", window, "sliding-window bundle adjustment");
    v.section("keyframes", keyframes, "when a frame becomes a keyframe");
    v.section("initializer", initializer, "monocular initialisation from the first frames");
    v.section("loop", loop, "loop closure");
    v.section("calibration", calibration, "online refinement of the camera calibration");
    v.section("reuse", reuse, "map reuse: map keyframes brought back into the window");
    v.section("map", map, "maps across sessions: a loaded map");
  }
};

/// Every problem with `config`, one message each naming the key and the allowed range
/// (empty when valid).
std::vector<std::string> configProblems(const Config& config);

/// Throws ldsm::ConfigError listing every problem when `config` is invalid.
void validateConfig(const Config& config);

}  // namespace ldsm
