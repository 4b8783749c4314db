// Configuration: a tree of plain structs with defaults. Every struct lists its fields once, in
// visit(), with key, allowed range and help text; validation, YAML loading and printing of the
// defaults are all driven from that single list (see config_visitors.h), so a field can never be
// documented in one place and forgotten in another. The larger sections have their own headers
// (ldsm/config/).
#pragma once

#include <string>
#include <vector>

#include "ldsm/config/calibration_config.h"
#include "ldsm/config/loop_config.h"
#include "ldsm/config/range.h"
#include "ldsm/config/reuse_config.h"

namespace ldsm {

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
  /// its points are inliers, or (tracked as usual, not searched for after a loss or a gap) past
  /// 0.6 times as many while fewer than three quarters are, is not this scene (a glitch, noise, a
  /// covered lens, a cut to another scene): tracking is lost there rather than accepting a garbage
  /// pose. 0 disables the check.
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
            "a frame with this many times the last residual and < 50 % inliers (or, outside "
            "the search after a loss or gap, 0.6 times as many and < 75 %) is lost (0: off)");
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
  /// Keyframes that are no longer the newest keep their level-0 intensities in 16-bit fixed
  /// point (steps of 1/128 grey level; 2 instead of 4 bytes per pixel; docs/engine.md, "Memory";
  /// trajectories not bit-identical to float).
  bool keyframe_images_16bit = false;

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
    v.field("keyframe_images_16bit", keyframe_images_16bit,
            "older window keyframes keep their level-0 intensities in 16 bits (half the memory "
            "of float, results not bit-identical to float)");
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
  /// A keyframe is made when fewer than this share of the reference's points in the frame are
  /// inliers of the tracking fit (0: never). The residual rule compares with the first frame
  /// tracked against the reference, which can already fit badly: on vamr_desk_loop after a gap the
  /// frames after a jerk fitted their new reference at 72 % inliers, sliding to 46 % over 17 frames
  /// and 3.6 cm off, with no keyframe and no loss. The tracked frames of the 12 checksum runs
  /// (real and rendered sequences, no gaps) stay above 80 % (docs/engine.md, "Keyframe rate").
  double min_inlier_fraction = 0.7;

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
    v.field("min_inlier_fraction", min_inlier_fraction, Range<double>{0.0, 1.0},
            "new keyframe when fewer than this share of the reference's points in the frame are "
            "tracking inliers (0: never)");
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
