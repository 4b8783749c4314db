// Monocular initialisation (after the idea of DSO's coarse initializer, designed here): the first
// frame becomes the reference and many points are selected on every pyramid level of it, with
// inverse depth 1. For each following frame, the frame's pose T_frame_ref, its affine brightness
// (a, b) and the inverse depths of ALL points are optimised jointly, coarse to fine, by
// Levenberg-Marquardt on Huber photometric residuals over the 8-pixel pattern. Each depth couples
// only to the 8 frame parameters, so the depths are eliminated by a Schur complement and an
// iteration costs O(points).
//
// Regularisation and gauge:
//  * Smoothness: each inverse depth is pulled towards the median of its k nearest neighbours on
//    the same level (links precomputed once; the medians are taken from the depths being
//    evaluated, so the energy is consistent, and held fixed in the linearisation). Strong while
//    the parallax is small, when depths are barely observable and would follow noise; off (by
//    default) once the parallax is real, so that it cannot bias the map.
//  * A weak prior pulls every inverse depth towards 1.
//  * Scale: after each level's optimisation the mean inverse depth of that level is normalised to
//    1 and the translation scaled to match. The photometric error is invariant under this, so it
//    only removes the scale freedom (which the smoothness term would shrink towards 0) and needs
//    no prior on the translation, which would bias a real motion.
//  * Coarse to fine: each point has a parent one level coarser. Before a level is optimised its
//    depths are blended with their parents' (weighted by the photometric Hessians); after a frame,
//    depths are propagated up (parent = Hessian-weighted mean of its children).
//  * The LM damping starts small (1e-3 of the diagonal): the rotation/translation/depth valleys
//    of small-baseline geometry are long and flat, and strong damping leaves the estimate stuck
//    at their entrance.
//
// Acceptance ("snap"): the RMS optical flow caused by the translation over the level-0 inliers
// exceeds min_parallax_flow pixels, at least min_rotation_free_parallax of it cannot be explained
// by a rotation (with free depths, a small translation can mimic a rotation: a static or purely
// rotating camera fits its noise that way, with large "translation flow" but no rotation-free
// parallax), the residual is low and most points are inliers. The snap must hold over
// confirm_frames more frames; then the depth distribution is checked (not mostly negative, not
// hugely spread) and the result published with the mean inverse depth of the inliers set to 1.
// Failures (too few textured points, points lost, a residual that explodes or jumps, degenerate
// depths) are reported; the next frame starts over as a new reference.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "camera/pyramid_camera.h"
#include "features/pixel_selector.h"
#include "frontend/coarse_initializer_settings.h"
#include "frontend/init_point_graph.h"
#include "image/image_pyramid.h"
#include "math/se3.h"
#include "model/affine_light.h"
#include "model/residual_pattern.h"

namespace ldsm {

class CoarseInitializer {
 public:
  /// Prepares for images of the camera's level-0 size. Throws ConfigError on invalid settings
  /// and InputError when the camera has no levels or a non-positive size.
  explicit CoarseInitializer(const PyramidCamera& camera,
                             const CoarseInitializerSettings& settings = {});

  /// Feeds one frame (exposure time `exposure`, 1 when unknown). The first frame (and the first
  /// after a failure or reset()) becomes the reference. Returns true when the initialisation is
  /// complete: result() is then valid. Frames fed after completion are tracked too (the result
  /// follows them) until reset(). Throws InputError when the pyramid does not match the
  /// camera's size, has too few levels, or the exposure is not a positive finite number.
  bool addFrame(const ImagePyramid& pyramid, double exposure);

  /// Starts over: the next frame becomes the reference.
  void reset();

  /// Takes `primary`'s reference (its points, levels and exposure; `primary` must have just set
  /// it, i.e. framesTracked() == 0) and starts tracking from the motion guess (identity rotation,
  /// translation `seed` in units of the mean inverse depth), so that several hypotheses can
  /// explore different basins of the same reference (InitializerHypotheses).
  void adoptReference(const CoarseInitializer& primary, const Eigen::Vector3d& seed);
  /// Takes the reference `source` is tracking (any number of frames in), with every depth back
  /// at its start (inverse depth 1) and `source`'s brightness estimate, and starts tracking from
  /// the motion guess `start` (scale: mean inverse depth 1): a fresh hypothesis for the same
  /// reference once the parallax is real (InitializerHypotheses). Frames are counted anew.
  void restartFrom(const CoarseInitializer& source, const SE3d& start);
  /// The camera moved on for `scale` times the time from the reference to the last frame before
  /// the next frame comes (frames went by that this initializer did not see): once the parallax
  /// is real (confirming), the motion guess for the next frame continues the estimated motion,
  /// its twist times `scale`; before that the estimate is mostly noise and stays the guess.
  /// Returns whether the guess moved (scale > 1, finite, confirming).
  bool continueMotion(double scale);
  /// reset() and give the reference's memory back (it is allocated again with the next one).
  void releaseMemory();
  /// Photometric cost of every level-0 point in the last frame (outliers at the cap): comparable
  /// between initializers that share a reference and saw the same frame.
  double photometricEnergy() const { return eval_.photo_all; }

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
    double photo_all = 0;    ///< photometric cost of all points (outliers at the cap)
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
  /// Every point of `L` back at its start: inverse depth 1, no linearisation, not an inlier.
  static void resetEstimates(Level& L);
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
  /// evaluate()'s last step: the lower triangle of H, the affine prior (weighted by the `n`
  /// points) and the depth priors' energy `reg_energy`; whether everything stayed finite.
  void addPriors(const AffineLight& affine, int n, double reg_energy, Evaluation& out) const;
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
