// Monocular initialisation (after the idea of DSO's coarse initializer): the first frame becomes
// the reference; many points are selected on every pyramid level of it with inverse depth 1. For
// each following frame, the frame's pose T_frame_ref, its affine brightness (a, b) and the inverse
// depths of ALL points are optimised jointly, coarse to fine, by Levenberg-Marquardt on Huber
// photometric residuals over the 8-pixel pattern. Each depth couples only to the 8 frame
// parameters, so the depths are eliminated by a Schur complement and an iteration is O(points).
//
// Regularisation and gauge:
//  * Smoothness: each inverse depth is pulled towards the median of its k nearest neighbours on
//    the same level (links precomputed once). Strong while the translation is small (the depths are
//    then barely observable and would otherwise follow noise); weak or off once the parallax is
//    real.
//  * A weak prior pulls every inverse depth towards 1.
//  * Scale: after every accepted step the mean inverse depth of the level is normalised to 1 and
//    the translation scaled to match. The photometric error is invariant under this, so it only
//    removes the scale freedom (which the smoothness term would otherwise shrink towards 0) and
//    needs no prior on the translation, which would bias the pose when the motion is real.
//  * Coarse to fine: each point has a parent one level coarser. Before a level is optimised its
//    depths are blended with their parents' (weighted by the photometric Hessians); after a frame,
//    depths are propagated up (parent = Hessian-weighted mean of its children).
//
// Acceptance: the parallax is real once the RMS optical flow caused by the translation alone over
// the level-0 points exceeds min_parallax_flow pixels, a good part of that flow cannot be explained
// by a rotation (with free depths, a small translation can mimic a rotation: for a static or
// purely rotating camera, noise is fitted that way), the residual is low and most points are
// inliers ("snap"). It is confirmed over confirm_frames more frames; then the depth distribution is
// checked (no mostly negative or hugely spread inverse depths) and the result published with the
// mean inverse depth normalised to 1. A static or purely rotating camera never produces that flow.
// Failures (too few points, points lost, residual explosion, degenerate depths) are reported so the
// caller can start over with a new reference.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "frontend/affine_light.h"
#include "frontend/init_point_graph.h"
#include "frontend/pixel_selector.h"
#include "frontend/pyramid_camera.h"
#include "frontend/residual_pattern.h"
#include "ldsm/config.h"
#include "ldsm/image/image_pyramid.h"
#include "ldsm/math/se3.h"

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
  int neighbours = 10;       ///< k of the smoothness neighbourhood (<= kMaxNeighbours)
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
  float affine_prior_weight_a = 10.f;
  float affine_prior_weight_b = 0.01f;

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

/// A reference point of the finished initialisation (level-0 pixel coordinates).
struct InitializedPoint {
  float u = 0, v = 0;
  float idepth = 1;   ///< inverse depth in the reference frame (mean over the map = 1)
  float hessian = 0;  ///< photometric Hessian of the inverse depth (information; 0: unknown)
  bool good = false;  ///< an inlier in the last frame
  bool is_corner = false;
};

struct InitializationResult {
  std::vector<InitializedPoint> points;
  SE3d T_frame_ref;          ///< reference -> last frame (translation in the map's scale)
  AffineLight affine_frame;  ///< last frame's affine brightness relative to the reference (0, 0)
  double exposure_ref = 1;
  double exposure_frame = 1;
  int frames = 0;  ///< frames tracked after the reference
};

/// Diagnostics of the last addFrame().
struct InitFrameStats {
  double flow_translation = 0;  ///< RMS level-0 flow due to translation alone (pixels)
  /// RMS of that flow after removing the part a rotation can explain (pixels): the parallax.
  double parallax = 0;
  double rms_residual = 0;      ///< level-0 Huber RMS residual of inlier points (grey levels)
  double good_fraction = 0;     ///< share of level-0 points that are inliers
  int iterations = 0;           ///< LM iterations over all levels
};

class CoarseInitializer {
 public:
  /// Prepares for images of the camera's level-0 size. Throws ConfigError on invalid settings
  /// and InputError when the camera has no levels or a non-positive size.
  explicit CoarseInitializer(const PyramidCamera& camera,
                             const CoarseInitializerSettings& settings = {});

  /// Feeds one frame (exposure time `exposure`, 1 when unknown). The first frame (and the first
  /// after a failure or reset()) becomes the reference. Returns true when the initialisation is
  /// complete: result() is then valid. Throws InputError when the pyramid does not match the
  /// camera's size, has too few levels, or the exposure is not a positive finite number.
  bool addFrame(const ImagePyramid& pyramid, double exposure);

  /// Starts over: the next frame becomes the reference.
  void reset();

  InitStatus status() const { return status_; }
  InitFailure failure() const { return failure_; }
  bool failed() const { return status_ == InitStatus::kFailed; }
  bool complete() const { return status_ == InitStatus::kComplete; }
  /// Frames tracked since the reference.
  int framesTracked() const { return frames_; }
  const InitFrameStats& lastFrameStats() const { return stats_; }
  /// Valid once addFrame() returned true.
  const InitializationResult& result() const { return result_; }
  /// Current estimate of reference -> newest frame (scale: mean inverse depth 1).
  const SE3d& currentPose() const { return T_; }

  int levels() const { return levels_; }
  int pointCount(int level) const { return static_cast<int>(levels_data_[level].u.size()); }
  const CoarseInitializerSettings& settings() const { return settings_; }

 private:
  friend struct CoarseInitializerAccess;

  /// A point's Schur data: coupling to [rho, phi, a, b], total depth Hessian (with priors),
  /// depth gradient, photometric depth Hessian alone and photometric energy (the outlier cost
  /// when the point is not an inlier).
  struct PointLinearization {
    Eigen::Matrix<float, 8, 1> hxd;
    float hdd;
    float bd;
    float hphoto;
    float energy;
  };
  struct Evaluation {
    Eigen::Matrix<double, 8, 8> H;
    Eigen::Matrix<double, 8, 1> b;
    double energy = 0;       ///< total: photometric (capped) + priors
    double photo_good = 0;   ///< Huber cost of inlier points
    int good = 0;            ///< inlier points
    double flow_sq_sum = 0;  ///< sum over inliers of squared translation flow (level-0 pixels)
    bool finite = true;
  };
  struct Level {
    std::vector<Eigen::Vector2f> u;                    ///< pixel at this level
    std::vector<std::array<float, kPatternSize>> ref;  ///< reference intensities
    std::vector<std::array<int, CoarseInitializerSettings::kMaxNeighbours>> neighbours;
    std::vector<int> neighbour_count;
    std::vector<int> parent;  ///< index one level up, -1: none
    std::vector<std::uint8_t> is_corner;
    std::vector<float> idepth, idepth_trial, ir, ir_trial;
    std::vector<PointLinearization> lin, lin_trial;
    std::vector<std::uint8_t> good, good_trial;
    std::vector<float> accum_w, accum_wd;  ///< propagation scratch
  };

  void setReference(const ImagePyramid& pyramid, double exposure);
  /// Selects the points of level `lvl` of the reference into levels_data_[lvl].u (and is_corner);
  /// returns the bucket size for neighbour searches.
  float selectPoints(const ImagePyramid& pyramid, int lvl);
  void checkFrame(const ImagePyramid& pyramid, double exposure) const;
  void fail(InitFailure failure);
  void trackFrame(const ImagePyramid& pyramid, double exposure);
  int optimiseLevel(int lvl);
  /// Energy of the level at (T, affine, idepth) with smoothness targets `ir`, and its linearisation
  /// (normal equations of [rho, phi, a, b] in `out`, the depths' Schur data in `lin`).
  void evaluate(int lvl, const SE3d& T, const AffineLight& affine, const float* idepth,
                const float* ir, PointLinearization* lin, std::uint8_t* good,
                Evaluation& out) const;
  bool computeStep(int lvl, double lambda, SE3d& T_new, AffineLight& affine_new);
  /// Rescales all depths and translations so that the mean inverse depth of `lvl` is 1.
  void normaliseScale(int lvl);
  /// ir[i] = median inverse depth of point i's neighbours (from `idepth`).
  void computeSmoothnessTargets(int lvl, const float* idepth, float* ir) const;
  void propagateDown(int lvl);
  void propagateUp();
  void decide();
  /// RMS (level-0 pixels) over the inliers of the translation-induced flow minus its best
  /// least-squares fit by a small rotation.
  double rotationFreeParallax() const;
  bool depthsDegenerate();
  void publishResult();

  CoarseInitializerSettings settings_;
  PyramidCamera camera_;
  int width_ = 0, height_ = 0;
  int levels_ = 0;
  std::array<Level, kMaxPyramidLevels> levels_data_;

  InitStatus status_ = InitStatus::kNoReference;
  InitFailure failure_ = InitFailure::kNone;
  int frames_ = 0;
  int snapped_frames_ = 0;  ///< frames since the snap
  double lowest_rms_ = 0;   ///< lowest level-0 RMS residual since the reference
  double exposure_ref_ = 1;
  double exposure_frame_ = 1;

  // Current frame (valid during trackFrame()).
  const ImagePyramid* frame_ = nullptr;
  float exposure_ratio_ = 1.f;
  float smoothness_weight_ = 0.f;

  SE3d T_;  ///< reference -> current frame
  AffineLight affine_;
  Evaluation eval_, eval_trial_;
  InitFrameStats stats_;
  InitializationResult result_;
  PointBucketGrid grid_;
  std::unique_ptr<PixelSelector> selector_;
  std::vector<SelectedPixel> selected_;
  std::vector<int> nn_scratch_;
  std::vector<float> sort_scratch_;
};

}  // namespace ldsm
