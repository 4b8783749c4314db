// Settings, status codes and result values of the monocular initializer (CoarseInitializer).
#pragma once

#include <array>
#include <vector>

#include "camera/pyramid_camera.h"
#include "ldsm/config.h"
#include "math/se3.h"
#include "model/affine_light.h"
#include "model/initialization_result.h"

namespace ldsm {

struct CoarseInitializerSettings {
  static constexpr int kMaxNeighbours = 10;

  int max_levels = 5;          ///< pyramid levels used (fewer when the image is small)
  int min_coarsest_size = 16;  ///< the coarsest used level keeps at least this width and height
  /// Point selection: best-gradient pixel per cell x cell block, per level (level 0 first).
  std::array<int, kMaxPyramidLevels> cell_size{{8, 6, 4, 2, 2, 2, 2, 2}};
  float min_gradient = 3.f;  ///< |grad I| (grey levels / pixel) a selected pixel must reach
  /// Level-0 points come from the keyframe PixelSelector (so that its corners, flagged is_corner,
  /// can carry descriptors later), about selection.points_per_keyframe * selector_density of
  /// them; the coarser levels always use the best-gradient-per-cell selection.
  bool use_pixel_selector = true;
  PointSelectionConfig selection;
  float selector_density = 2.f;
  int neighbours = 10;  ///< k of the smoothness neighbourhood (<= kMaxNeighbours)
  /// Levenberg-Marquardt iterations per level (level 0 first).
  std::array<int, kMaxPyramidLevels> max_iterations{{4, 6, 10, 15, 20, 20, 20, 20}};
  double initial_lambda = 1e-3;  ///< LM damping (Marquardt: relative to the Hessian's diagonal)
  /// A level stops when an accepted step lowers the energy by less than this fraction.
  double convergence_energy_fraction = 1e-3;

  float huber_threshold = 9.f;     ///< Huber threshold of residuals, grey levels
  float gradient_weight_c = 50.f;  ///< c of the weight c^2 / (c^2 + |grad I|^2); 0 disables
  /// A point whose pattern RMS residual exceeds this (grey levels) is an outlier: it costs a
  /// constant and does not enter the normal equations.
  float outlier_rms = 30.f;

  /// Weight of (d - median of neighbours)^2 per point (grey levels^2 per unit inverse depth^2)
  /// before and after the parallax is real.
  float smoothness_weight = 300.f;
  float smoothness_weight_parallax = 0.f;
  float idepth_prior_weight = 1.f;  ///< weight of (d - 1)^2 per point
  /// Weights of a^2 and b^2 per point of the level (keep affine brightness from eating geometry).
  /// A point's own data weighs about 8 I^2 ~ 1e5 on a and 8 on b: the defaults are weak priors
  /// for unknown exposures; with known exposures (a, b) are held near 0 by
  /// kAffinePriorKnownA/B.
  float affine_prior_weight_a = 10.f;
  float affine_prior_weight_b = 0.01f;
  static constexpr float kAffinePriorKnownA = 1e7f;
  static constexpr float kAffinePriorKnownB = 1e3f;

  // ---- acceptance
  /// RMS flow due to translation (level-0 pixels) that counts as real parallax...
  float min_parallax_flow = 6.f;
  /// ...when at least this much of it (RMS, level-0 pixels) cannot be explained by a rotation.
  /// Catches translations that only mimic a rotation (static or rotating camera, depths fitted
  /// to noise).
  float min_rotation_free_parallax = 1.5f;
  float max_snap_rms = 10.f;              ///< level-0 Huber RMS residual allowed when snapping
  float min_snap_good_fraction = 0.6f;    ///< share of level-0 points that must be inliers to snap
  int confirm_frames = 5;                 ///< frames after the snap before the result is accepted
  float max_nonpositive_fraction = 0.1f;  ///< accepted map: share of inverse depths <= 0
  float max_idepth_spread = 10.f;         ///< accepted map: 95th percentile / median inverse depth

  // ---- failure
  int min_points = 100;            ///< fewer selected level-0 points: refuse the reference
  float min_good_fraction = 0.3f;  ///< fewer level-0 inliers: tracking lost
  float fail_rms = 25.f;           ///< level-0 Huber RMS residual that means tracking is lost
  /// Tracking is also lost when the RMS residual exceeds this multiple of the lowest one since
  /// the reference (and residual_growth_floor): free depths can fit almost any image along the
  /// epipolar lines, so a wrong frame shows up as a jump of the residual, not as an explosion.
  float max_residual_growth = 2.5f;
  float residual_growth_floor = 3.f;  ///< grey levels

  /// Throws ConfigError naming the first invalid field.
  void validate() const;
};

enum class InitStatus {
  kNoReference,         ///< nothing yet: the next frame becomes the reference
  kWaitingForParallax,  ///< tracking, translation still too small
  kConfirming,          ///< parallax reached, confirming over a few frames
  kComplete,            ///< result() is valid
  kFailed,              ///< see failure(); the next frame starts over as the new reference
};

enum class InitFailure {
  kNone,
  kTooFewPoints,      ///< the reference has too little texture
  kLostTrack,         ///< too few points stay in the image / are inliers
  kResidualTooLarge,  ///< the photometric error exploded
  kNotFinite,         ///< NaN or infinity in the estimate
  kDegenerateDepths,  ///< accepted map with mostly negative or hugely spread inverse depths
};

const char* toString(InitStatus status);
const char* toString(InitFailure failure);

/// Diagnostics of the last addFrame().
struct InitFrameStats {
  double flow_translation = 0;  ///< RMS level-0 flow due to translation alone (pixels)
  /// RMS of that flow after removing the part a rotation can explain (pixels): the parallax.
  double parallax = 0;
  double rms_residual = 0;   ///< level-0 Huber RMS residual of inlier points (grey levels)
  double good_fraction = 0;  ///< share of level-0 points that are inliers
  int iterations = 0;        ///< LM iterations over all levels
};

}  // namespace ldsm
