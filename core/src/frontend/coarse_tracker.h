// Coarse tracking of a new frame against the newest keyframe (DSO, "Initial Frame Tracking"):
// the window's points projected into the reference become per-level inverse-depth maps
// (DepthMapPyramid), and the frame's pose T_frame_ref and affine brightness (a, b) are found by
// Levenberg-Marquardt on the Huber-weighted photometric error, coarse to fine over the pyramid.
#pragma once

#include <Eigen/Core>
#include <array>
#include <bitset>
#include <cstddef>
#include <limits>
#include <vector>

#include "camera/pyramid_camera.h"
#include "frontend/coarse_residuals.h"
#include "frontend/depth_map_pyramid.h"
#include "image/image_pyramid.h"
#include "math/se3.h"
#include "model/affine_light.h"

namespace ldsm {

/// One value per pyramid level (only the tracked levels are meaningful).
using LevelValues = Eigen::Matrix<double, kMaxPyramidLevels, 1>;

/// LevelValues filled with +infinity: "no abort threshold".
inline LevelValues noAbortThresholds() {
  return LevelValues::Constant(std::numeric_limits<double>::infinity());
}

struct CoarseTrackerSettings {
  float huber_threshold = 9.f;  ///< Huber threshold of residuals, grey levels
  /// Levenberg-Marquardt iterations per level (level 0 first).
  std::array<int, kMaxPyramidLevels> max_iterations{{10, 20, 50, 50, 50, 50, 50, 50}};
  float border_margin = 2.f;           ///< projections closer to the border are skipped (pixels)
  float min_in_image_fraction = 0.2f;  ///< a level fails when fewer of its points are in the frame
  /// Residuals larger than this (grey levels) are outliers (occlusions, specularities): they add
  /// a constant cost and no gradient.
  float outlier_threshold = 20.f;
  /// Tracking fails when, on level 0, fewer residuals than this are below outlier_threshold.
  float min_inlier_fraction = 0.3f;
  /// While more residuals of a level than this are outliers, the outlier threshold is doubled
  /// (at most max_threshold_doublings times) and the level is run once more afterwards.
  float outlier_fraction_for_doubling = 0.6f;
  int max_threshold_doublings = 6;
  /// Tracking fails when the frame's affine brightness leaves |a - a_ref| <= max_affine_a_change,
  /// |b - b_ref| <= max_affine_b_change: the degenerate "solution" of a wrong pose is contrast
  /// 0 (a -> -inf) and b = the mean intensity.
  double max_affine_a_change = 1.2;
  double max_affine_b_change = 200.0;
  /// c of the gradient-dependent weight c^2 / (c^2 + |grad I_ref|^2); 0 disables it.
  float gradient_weight_c = 0.f;
  /// Weights of the prior (a - a_ref)^2 and (b - b_ref)^2 on the frame's affine brightness.
  double affine_prior_weight_a = 1e-3;
  double affine_prior_weight_b = 1e-3;
  /// Per-point weights of the prior (a - a_pred)^2 and (b - b_pred)^2 towards the predicted
  /// brightness (the last frame's): real cameras change gain and exposure by a few percent per
  /// frame, while a wrong pose can lower the residual by flattening the contrast (a -> -inf, b ->
  /// mean). With the mean energy per point near rmse^2 (~50), a = 0.1 costs 0.5 and a = 0.9 costs
  /// 40 per point.
  double affine_change_prior_a = 50.0;
  double affine_change_prior_b = 0.01;
  double initial_lambda = 0.01;  ///< LM damping of the Jacobi-scaled normal equations
  /// A level stops when a step would change the residuals by less than this (RMS, grey levels)
  /// or after max_rejected_steps steps in a row failed to lower the cost.
  double convergence_rms_step = 5e-3;
  int max_rejected_steps = 3;
  /// A level that a finer one follows also ends after an accepted step that lowered the cost by
  /// less than this share of it: the finer level refines from there. The coarse levels' last
  /// 0.1 % took most of their iterations (vamr_desk_loop: 10.8 evaluations per level;
  /// docs/engine.md, "Stopping the coarse levels early"). The finest level tracked (level 0, or
  /// a coarse one when only that is tracked, as the screening of rotated guesses does) runs as
  /// before. 0: every level runs until a step is too small or rejected.
  double coarse_level_min_relative_decrease = 1e-3;
};

enum class TrackingFailure {
  kNone,
  kNoReference,       ///< setReference() was not called or left no points on a level
  kTooFewInImage,     ///< too few points project into the frame
  kNotFinite,         ///< the residual became NaN or infinite
  kResidualTooLarge,  ///< a level's RMSE exceeded its abort threshold
  kTooFewInliers,     ///< most residuals are outliers (not the same image content)
  kAffineOutOfRange,  ///< the affine brightness change is implausibly large
};

/// Human-readable name of a TrackingFailure.
const char* toString(TrackingFailure failure);

struct CoarseTrackingResult {
  bool success = false;
  TrackingFailure failure = TrackingFailure::kNone;
  int failed_level = -1;  ///< the level tracking stopped at, -1 on success
  /// Huber RMSE (grey levels) per level at the end of the level; NaN for levels not tracked.
  LevelValues rmse = LevelValues::Constant(std::numeric_limits<double>::quiet_NaN());
  double inlier_fraction = 0;    ///< level 0: share of residuals below the outlier threshold
  double in_image_fraction = 0;  ///< level 0: share of points projecting into the frame
  int iterations = 0;            ///< LM iterations over all levels
  /// Root-mean-square optical flow of the level-0 points (pixels) for the full motion, for the
  /// translation alone (rotation removed) and for the rotation alone.
  double flow_full = 0;
  double flow_translation = 0;
  double flow_rotation = 0;
  /// Cells of a coarse grid over the image that the reference's points occupy in the frame, over
  /// those they occupy in the reference (1 at the reference; falls as its points leave the view
  /// or, when the camera backs away, gather towards the centre and leave the borders to parts of
  /// the scene the reference has no points for).
  double coverage = 1;
  double brightness_scale = 1;  ///< s = exp(a - a_ref) e_frame / e_ref
};

class CoarseTracker {
 public:
  /// Preallocates the settings and sizes for width x height images and `levels` pyramid levels
  /// (the point lists grow with the references set).
  CoarseTracker(int width, int height, int levels, const CoarseTrackerSettings& settings);

  /// Sets the reference keyframe: its pyramid (at least levels() levels of the constructed size),
  /// camera, the window's points projected into it, its exposure time (1 when unknown) and affine
  /// brightness. The depth maps are splatted into `canvas` (the builder's scratch, which the
  /// trackers one thread prepares can share) or, when null, into a canvas this tracker allocates
  /// at its first such call. `radial_k` is the residual radial distortion of the reference's and
  /// the frames' images (camera/radial_distortion.h; the window's applied correction): the points
  /// are then pixels of the distorted images, their rays are undistorted once here, and every
  /// warp projects through the distortion (kernels/coarse_warp.h). Allocates nothing else (the
  /// point lists grow to the most points seen).
  void setReference(const ImagePyramid& reference, const PyramidCamera& camera,
                    const DepthPoint* points, std::size_t count, double exposure,
                    const AffineLight& affine, DepthMapCanvas* canvas = nullptr,
                    float radial_k = 0.f);
  void setReference(const ImagePyramid& reference, const PyramidCamera& camera,
                    const std::vector<DepthPoint>& points, double exposure,
                    const AffineLight& affine, DepthMapCanvas* canvas = nullptr,
                    float radial_k = 0.f) {
    setReference(reference, camera, points.data(), points.size(), exposure, affine, canvas,
                 radial_k);
  }

  /// Tracks `frame` (exposure time `exposure`) from level min(coarsest_level, levels() - 1) down
  /// to `finest_level` (0: the full resolution). T_frame_ref and affine hold the initial guess and
  /// receive the estimate (also when tracking fails). A level whose final RMSE exceeds
  /// max_rmse[level] aborts tracking. Returns result.success; stopped above level 0, the result
  /// has only the RMSE of the levels tracked (no inlier, flow or brightness figures). Allocates
  /// nothing.
  bool track(const ImagePyramid& frame, double exposure, SE3d& T_frame_ref, AffineLight& affine,
             int coarsest_level, const LevelValues& max_rmse, CoarseTrackingResult& result,
             int finest_level = 0);

  /// The residual of reference point `index` of `level` for the given parameters, and its
  /// Jacobian w.r.t. [rho, phi, a, b] (left perturbation of T) when `jacobian` is not null.
  /// Returns false when the point does not project into the frame. For tests and diagnostics.
  bool pointResidual(const ImagePyramid& frame, double exposure, const SE3d& T_frame_ref,
                     const AffineLight& affine, int level, int index, float* residual,
                     float* jacobian) const;

  int levels() const { return depth_maps_.levels(); }
  const DepthMapPyramid& depthMaps() const { return depth_maps_; }
  const CoarseTrackerSettings& settings() const { return settings_; }
  bool hasReference() const { return has_reference_; }
  /// The residual radial distortion the reference was set with.
  float radialK() const { return radial_k_; }
  const AffineLight& referenceAffine() const { return ref_affine_; }
  double referenceExposure() const { return ref_exposure_; }

 private:
  struct Evaluation {
    double energy = 0;        // sum of weighted Huber costs (2 rho(r)), outliers included
    double huber_sq_sum = 0;  // the same without gradient-dependent weights, for the RMSE
    int in_image = 0;         // points projecting into the frame
    int inliers = 0;          // residuals in the normal equations
    int outliers = 0;         // residuals above the (possibly doubled) outlier threshold
    int base_inliers = 0;     // residuals below the configured outlier threshold
    bool finite = true;
    double rmse() const;
    double meanEnergy() const;
  };

  Evaluation evaluate(const ImagePyramid& frame, double exposure, int level, const SE3d& T,
                      const AffineLight& affine, float cutoff);
  template <bool kRadial>
  Evaluation evaluateLevel(const ImagePyramid& frame, double exposure, int level, const SE3d& T,
                           const AffineLight& affine, float cutoff);
  /// The pinhole pixels of a level's reference rays: the points' own pixels without a radial
  /// distortion, undistorted ones with it.
  const float* rayX(int level) const;
  const float* rayY(int level) const;
  /// Runs LM on one level; returns the final evaluation (and updates T, affine, cutoff).
  /// `refined_further`: a finer level follows (the early stop of the coarse levels applies).
  Evaluation optimiseLevel(const ImagePyramid& frame, double exposure, int level,
                           bool refined_further, SE3d& T, AffineLight& affine, float& cutoff,
                           int& iterations);
  void addAffinePrior(const AffineLight& affine, int points, CoarseMatrix& H,
                      CoarseVector& g) const;
  /// Prior energy per point (`points` in the evaluation).
  double affinePriorEnergy(const AffineLight& affine, int points) const;
  void computeFlow(const SE3d& T, CoarseTrackingResult& result) const;
  void computeCoverage(const SE3d& T, CoarseTrackingResult& result) const;
  /// The coverage grid cell of level-0 pixel (u, v), -1 outside the image.
  int coverageCell(float u, float v) const;
  double scaleOf(double exposure, const AffineLight& affine) const;

  CoarseTrackerSettings settings_;
  DepthMapPyramid depth_maps_;
  /// Coverage grid (CoarseTrackingResult::coverage): kCoverageColumns x kCoverageRows cells; those
  /// the reference's level-0 points occupy, set once per reference.
  static constexpr int kCoverageColumns = 16, kCoverageRows = 12;
  std::bitset<kCoverageColumns * kCoverageRows> reference_cells_;
  PyramidCamera camera_;
  float radial_k_ = 0.f;
  /// Per level, the undistorted pinhole pixels of the reference points (filled only while
  /// radial_k_ != 0; they grow like the point lists).
  std::array<std::vector<float>, kMaxPyramidLevels> ray_x_, ray_y_;
  WarpedResiduals warped_;
  double ref_exposure_ = 1;
  AffineLight ref_affine_;
  AffineLight predicted_affine_;  // centre of the brightness-change prior (the start value)
  bool has_reference_ = false;
};

}  // namespace ldsm
