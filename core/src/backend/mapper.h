// The mapping module: owns the sliding window of keyframes, inserts new keyframes, traces and
// activates immature points, runs the window bundle adjustment and marginalises old keyframes and
// their points into the prior. What the map keeps (keyframe poses, points that left the window,
// keyframes that left it) comes out of every operation as values (MapUpdate).
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "backend/distance_map.h"
#include "backend/marginalization_prior.h"
#include "backend/window_keyframe.h"
#include "backend/window_optimizer.h"
#include "camera/pyramid_camera.h"
#include "features/pixel_selector.h"
#include "image/pyramid_pool.h"
#include "ldsm/config.h"
#include "model/depth_point.h"
#include "model/initialization_result.h"
#include "model/map_records.h"
#include "model/marginalized_keyframe.h"
#include "model/tracking_reference.h"

namespace ldsm {

/// A tracked frame as the mapper sees it.
struct MapperFrame {
  std::int64_t frame_index = 0;
  double timestamp = 0.0;
  double exposure = 1.0;  ///< exposure time (1 when unknown)
  SE3d T_c_w;
  AffineLight aff;
};

/// The Mapper's settings: its sections of the configuration and what is derived from them.
struct MapperSettings {
  WindowConfig window;
  PointSelectionConfig points;
  CalibrationRefinementConfig calibration;
  WindowOptimizerSettings optimizer;
  float trace_huber_threshold = 9.f;
  float trace_outlier_threshold = 12.f;
};

/// What the window hands to the map after an operation, as values, in the order they arose.
struct MapUpdate {
  std::vector<HostedPoint> points;         ///< points that left the window
  std::vector<KeyframeRecord> keyframes;   ///< poses: keyframes that left, then the window's
  std::vector<MarginalizedKeyframe> left;  ///< keyframes that left the window
};

/// What happened when a keyframe was inserted.
struct KeyframeInsertion {
  int keyframe_id = -1;
  WindowOptimizationResult optimization;
  int activated_points = 0;
  int marginalized_frames = 0;
  int retired_points = 0;  ///< points that left the view (marginalised or dropped)
  int active_points = 0;
  int immature_points = 0;
  /// Points of reactivated map keyframes that are inliers in the new keyframe.
  int map_points_in_view = 0;
  MapUpdate map;  ///< for the map store and loop closure
};

class Mapper {
 public:
  Mapper(const MapperSettings& settings, const PyramidCamera& camera, PyramidPool& pyramids);
  ~Mapper();

  bool initialized() const { return !window_.empty(); }
  /// The tracing (per keyframe) and the window optimisation's linearisation (per host keyframe)
  /// run as parallel tasks on `tasks` from now on (not owned; null: one thread); bit-identical
  /// results either way.
  void setParallelTasks(concurrency::ParallelTasks* tasks) {
    tasks_ = tasks;
    optimizer_.setParallelTasks(tasks);
  }

  /// Starts the window from a finished initialisation: the reference frame becomes keyframe 0
  /// (gauge anchor, identity pose) with the initializer's points; the last frame is inserted as
  /// the second keyframe. Returns false when too few usable points remain.
  bool initialize(const InitializationResult& result, const MapperFrame& reference,
                  std::unique_ptr<ImagePyramid> reference_pyramid, const MapperFrame& last,
                  std::unique_ptr<ImagePyramid> last_pyramid, KeyframeInsertion* insertion);

  /// Narrows the depth intervals of every window keyframe's immature points with a new frame.
  void traceFrame(const ImagePyramid& frame, const MapperFrame& info);

  /// Inserts a tracked frame as a new keyframe (takes its pyramid) and optimises the window.
  KeyframeInsertion addKeyframe(std::unique_ptr<ImagePyramid> pyramid, const MapperFrame& info);

  const WindowKeyframe& newestKeyframe() const { return *window_.back(); }
  /// Bytes of image data the window holds: the level-0 intensities of each keyframe
  /// (ImagePyramid::compact), and the newest keyframe's whole pyramid until
  /// compactNewestImage(). Not counted: the compacted pyramids of keyframes that just left,
  /// held until then (leaving_pyramids_).
  std::size_t windowImageBytes() const;
  /// Frees all but the newest keyframe's level-0 intensities, once the tracking reference was
  /// made from it (a newer keyframe frees the rest anyway).
  /// Then gives the pyramids of the keyframes that left the window back to the pool.
  void compactNewestImage() {
    if (!window_.empty()) window_.back()->compactPyramid(settings_.window.keyframe_images_16bit);
    releaseLeavingPyramids();
  }
  /// The newest keyframe as the tracker's reference (its pyramid stays owned by the window).
  TrackingReference newestReference() const;
  /// Every active point of the window projected into the newest keyframe.
  void trackingPoints(std::vector<DepthPoint>& out) const;
  int activePointCount() const;
  /// Drops the window (tracking lost); returns the window keyframes' last poses for the map and,
  /// when leaving keyframes are described, the keyframes themselves (as if they had left).
  MapUpdate reset();
  /// Starts a window from a relocalised frame: it becomes the first keyframe (gauge anchor) at
  /// `info.T_c_w`, and `anchor` (the map keyframe it was found in, at pose T_w_c and scale) is
  /// reactivated so that tracking has the map's points to follow. Returns its insertion.
  KeyframeInsertion relocalize(std::unique_ptr<ImagePyramid> pyramid, const MapperFrame& info,
                               const MarginalizedKeyframe& anchor, const SE3d& anchor_T_w_c,
                               double anchor_scale);
  /// The window's keyframes as they would leave it now (their points, corners with depths and,
  /// when leaving keyframes are described, their images), the window unchanged: for a saved map.
  std::vector<MarginalizedKeyframe> describeWindow();
  /// Keyframe ids continue after `next` (a loaded map's keyframes keep theirs). Before the first
  /// keyframe only.
  void setNextKeyframeId(int next) { next_keyframe_id_ = next; }
  /// A loaded map's focal and principal point correction (CalibrationRefinement::startAt): the
  /// window works in the camera the map was measured in. Before the first keyframe.
  void startCalibrationAt(double focal_log_scale, double cx_shift, double cy_shift);
  /// The first keyframe of the window's chain (the window started at initialisation or
  /// relocalisation with it): keyframes with smaller ids came from earlier chains or sessions.
  int chainStartId() const { return chain_start_id_; }
  /// The window keyframes' current poses.
  std::vector<KeyframeRecord> windowPoses() const;
  /// World positions of the active points.
  std::vector<MapPoint> activeMapPoints() const;
  // ---- Map reuse: map keyframes brought back into the window (reuse/, docs/map-reuse.md) ----
  /// Brings a map keyframe back: it hosts its points (fixed depths, scaled by 1/scale after a
  /// loop correction of the map) with residuals in every active keyframe; its pose T_w_c and
  /// brightness stay fixed. Replaces an earlier reactivation of the same keyframe.
  void reactivate(const MarginalizedKeyframe& keyframe, const SE3d& T_w_c, double scale);
  /// Takes a reactivated keyframe out of the window again (its points and residuals go).
  void deactivate(int keyframe_id);
  void deactivateAll();
  /// The dormant candidates of every window keyframe become immature candidates (called when a
  /// map keyframe leaves the window: the pixels it covered need points of the window's own).
  void wakeDormantPoints();
  /// Moves a reactivated keyframe (a loop or map correction moved the map under it) to T_w_c,
  /// its points' depths scaled with the map (scale_ratio: new / old scale). False when it is not
  /// in the window.
  bool moveReactivated(int keyframe_id, const SE3d& T_w_c, double scale_ratio);
  /// Ids of the reactivated keyframes.
  std::vector<int> reactivatedIds() const;
  /// For each reactivated keyframe: inlier and total residuals (in the image) of its points in
  /// the newest keyframe, as the last optimisation left them (before outliers were dropped).
  struct ReactivatedFit {
    int id = -1;
    int inliers = 0;
    int residuals = 0;
    /// At least `fraction` of its residuals in the newest keyframe are inliers (and it has some).
    bool fitsAt(double fraction) const {
      return residuals > 0 && inliers >= fraction * static_cast<double>(residuals);
    }
  };
  const std::vector<ReactivatedFit>& reactivatedFit() const { return reactivated_fit_; }
  /// What a window optimisation with the reactivated keyframes would do, tried and undone: the
  /// RMSE of the residuals hosted by the window's own keyframes before and after it, and each
  /// reactivated keyframe's fit in the newest keyframe after it. The window's state (poses,
  /// brightness, depths, residual states) is exactly as before the call.
  struct ReactivationTrial {
    double own_rmse_before = 0.0;
    double own_rmse_after = 0.0;
    std::vector<ReactivatedFit> fits;
  };
  ReactivationTrial tryReactivated();
  /// The newest keyframe's corners plus as many more as loop closure describes (the same
  /// detector and thresholds), for matching it against map keyframes.
  std::vector<Eigen::Vector2f> newestDescribableCorners();
  /// New points are not selected within this many pixels of a map point seen in the new keyframe
  /// (0: no such check).
  void setCoverageRadius(float pixels) { coverage_radius_ = pixels; }

  /// Whether keyframes that leave the window are described for loop closure (more corners with
  /// depths, the level-0 image in MapUpdate::left); off, they carry pose and points only. When on,
  /// each new keyframe gets up to `loop_corners.max_corners` Shi-Tomasi corners of at least
  /// `loop_corners.min_score` (WindowKeyframe::loop_corners), from the scores its point selection
  /// computes anyway.
  void setDescribeLeavingKeyframes(bool on, PixelSelector::CornerLimits loop_corners = {}) {
    describe_leaving_ = on;
    loop_corner_limits_ = on ? loop_corners : PixelSelector::CornerLimits{};
  }

  /// The radial correction the window applies (calibration_refinement.h).
  float radialK() const { return static_cast<float>(calibration_.applied()[kCalibRadial]); }
  /// The current estimate of the radial correction (applied or not).
  double radialEstimate() const { return calibration_.estimate()[kCalibRadial]; }
  /// The calibration refinement: the correction applied, its estimate and uncertainty.
  const CalibrationRefinement& calibration() const { return calibration_; }
  /// The camera the window works with: the configured pinhole with the focal length and
  /// principal point corrections applied (the radial one is radialK()).
  const PyramidCamera& camera() const { return camera_; }
  /// The camera as configured.
  const PyramidCamera& baseCamera() const { return base_camera_; }

 private:
  /// The optimisation window: the active keyframes, then the reactivated ones.
  std::vector<WindowKeyframe*> windowView() const;
  /// The active keyframes only (marginalisation).
  std::vector<WindowKeyframe*> activeView() const;
  /// Drops residuals of reactivated points that are no longer inliers, and points without any.
  void pruneReactivatedPoints();
  /// Marks the pixels of `kf` within coverage_radius_ of an inlier map point (coverage_).
  void markMapCoverage(const WindowKeyframe& kf);
  WindowKeyframe& insertKeyframe(std::unique_ptr<ImagePyramid> pyramid, const MapperFrame& info);
  void addResidualsToNewest();
  /// Fuses the window's calibration step and hands the resulting correction to the optimiser.
  void refineCalibration(const WindowOptimizationResult& opt);
  /// The window's camera and the optimiser's become the configured one with the refinement's
  /// applied correction.
  void useAppliedCalibration();
  int activatePoints();
  bool optimizeNewPointDepth(ActivePoint& point, const std::vector<FramePairPrecalc>& pairs);
  /// Sets the keyframe's outlier threshold from the energies of the residuals aimed at it.
  void adaptOutlierThreshold(WindowKeyframe& kf);
  void removeBadResiduals();
  /// Takes points the newest keyframe no longer sees out of the window (point_retirement.cpp).
  int retireLostPoints();
  int marginalizeFrames();
  std::vector<int> framesToMarginalize() const;
  void marginalizeFrame(int window_index);
  /// New immature points (and corners) for `kf`, not where map points are seen when
  /// `use_coverage` (their residuals in `kf` must have been evaluated).
  void makeImmaturePoints(WindowKeyframe& kf, bool use_coverage = true);
  MapPoint worldPoint(const ActivePoint& p) const;
  /// The keyframe as it leaves the window (its corners and their depths filled in first).
  MarginalizedKeyframe describeLeavingKeyframe(WindowKeyframe& f, std::vector<PatchPoint> points);
  /// The relative poses of `f` to every other keyframe of the window, as the window has them now.
  std::vector<KeyframeLink> linksOf(const WindowKeyframe& f) const;
  /// Keeps the inverse depth of a corner point in its host's corner list.
  static void recordCornerDepth(const ActivePoint& p);

  /// Soft anchor of a relocalised keyframe (per parameter; the photometric terms of a keyframe
  /// are 1e5-1e8 on its pose's diagonal).
  static constexpr double kRelocalizationAnchorWeight = 1e3;
  MapperSettings settings_;
  PyramidCamera base_camera_;  ///< as configured
  PyramidCamera camera_;       ///< with the calibration correction applied
  PyramidPool& pyramids_;
  /// Pyramids of keyframes that left the window, given back to the pool (which expands them to
  /// whole pyramids again) only once the newest keyframe is compacted (compactNewestImage(), or
  /// the next insertion at the latest): a whole spare pyramid and the newest keyframe's whole
  /// pyramid are then never held at once.
  std::vector<std::unique_ptr<ImagePyramid>> leaving_pyramids_;
  void releaseLeavingPyramids();
  WindowOptimizer optimizer_;
  concurrency::ParallelTasks* tasks_ = nullptr;
  CalibrationRefinement calibration_;
  MarginalizationPrior prior_;
  PixelSelector selector_;
  TraceSettings trace_settings_;
  std::vector<std::unique_ptr<WindowKeyframe>> window_;
  std::vector<std::unique_ptr<WindowKeyframe>> reactivated_;  ///< map keyframes brought back
  std::vector<float> energies_;                               // scratch of adaptOutlierThreshold()
  std::vector<SelectedPixel> selected_;
  int next_keyframe_id_ = 0;
  int chain_start_id_ = 0;
  std::uint64_t next_point_id_ = 0;
  float min_activation_distance_ = 2.f;
  DistanceMap activation_distance_;  ///< activatePoints()' spacing map, kept for its memory
  MapUpdate update_;                 ///< collected during the current operation
  float coverage_radius_ = 0.f;
  std::vector<ReactivatedFit> reactivated_fit_;
  /// The fit of each reactivated keyframe in the newest keyframe now.
  std::vector<ReactivatedFit> measureReactivatedFit() const;
  std::vector<std::uint8_t> coverage_;  ///< scratch of makeImmaturePoints()
  bool describe_leaving_ = false;
  PixelSelector::CornerLimits loop_corner_limits_;
  std::vector<Corner> loop_corner_scratch_;
  /// Copies loop_corner_scratch_ into the keyframe's loop corners.
  void takeLoopCorners(WindowKeyframe& kf);
  /// Corners detected on a keyframe leaving the window, for loop closure (at most
  /// loop.corners_per_keyframe, Shi-Tomasi score >= loop.corner_min_score).
};

}  // namespace ldsm
