// The online calibration refinement section of the configuration tree (ldsm/config.h).
#pragma once

#include "ldsm/config/range.h"

namespace ldsm {

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

}  // namespace ldsm
