// The mapping module: owns the sliding window of keyframes, inserts new keyframes, traces and
// activates immature points, runs the window bundle adjustment and marginalises old keyframes and
// their points into the prior. Finished keyframe poses and points go to the MapStore.
#pragma once

#include <functional>
#include <memory>
#include <mutex>
#include <vector>

#include "backend/marginalization_prior.h"
#include "backend/window_optimizer.h"
#include "camera/pyramid_camera.h"
#include "frontend/coarse_initializer.h"
#include "frontend/depth_map_pyramid.h"
#include "frontend/pixel_selector.h"
#include "ldsm/config.h"
#include "map/map_store.h"
#include "map/window_keyframe.h"
#include "model/marginalized_keyframe.h"

namespace ldsm {

/// A tracked frame as the mapper sees it.
struct MapperFrame {
  std::int64_t frame_index = 0;
  double timestamp = 0.0;
  double exposure = 1.0;  ///< exposure time (1 when unknown)
  SE3d T_c_w;
  AffineLight aff;
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
};

class Mapper {
 public:
  /// `photometry_known`: response, vignette and exposure times are known, so affine brightness
  /// is held near zero by the strong prior (photometric.affine_prior_weight_known).
  Mapper(const Config& config, const PyramidCamera& camera, MapStore& store, bool photometry_known);
  ~Mapper();

  bool initialized() const { return !window_.empty(); }

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
  /// Every active point of the window projected into the newest keyframe.
  void trackingPoints(std::vector<DepthPoint>& out) const;
  int activePointCount() const;
  /// Drops the window (tracking lost); keyframes keep their last poses in the map store.
  void reset();
  /// A pyramid for a new frame, from a pool of released ones when possible. The pool may be used
  /// from the tracking and the mapping thread at once.
  std::unique_ptr<ImagePyramid> acquirePyramid();
  void releasePyramid(std::unique_ptr<ImagePyramid> pyramid);
  /// Writes the window keyframes' current poses to the map store.
  void publishPoses() const;
  /// World positions of the active points.
  std::vector<MapPoint> activeMapPoints() const;
  /// Called with each keyframe that leaves the window, as a value (final pose, points, corners
  /// with depths, level-0 image), on the mapping thread.
  void setKeyframeLeavingHandler(std::function<void(MarginalizedKeyframe&&)> handler) {
    on_leaving_ = std::move(handler);
  }

  /// The radial correction the window applies (radial_correction.h).
  float radialK() const { return static_cast<float>(radial_.applied()); }
  /// The current estimate of the radial correction (applied or not).
  double radialEstimate() const { return radial_.estimate(); }

 private:
  std::vector<WindowKeyframe*> windowView() const;
  WindowKeyframe& insertKeyframe(std::unique_ptr<ImagePyramid> pyramid, const MapperFrame& info);
  void addResidualsToNewest();
  /// Fuses the window's radial step and hands the resulting correction to the optimiser.
  void refineRadialCorrection(const WindowOptimizationResult& opt);
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
  void makeImmaturePoints(WindowKeyframe& kf);
  MapPoint worldPoint(const ActivePoint& p) const;
  /// The keyframe as it leaves the window (its corners and their depths filled in first).
  MarginalizedKeyframe describeLeavingKeyframe(WindowKeyframe& f, std::vector<PatchPoint> points);
  /// Keeps the inverse depth of a corner point in its host's corner list.
  static void recordCornerDepth(const ActivePoint& p);

  Config config_;
  PyramidCamera camera_;
  MapStore& store_;
  WindowOptimizer optimizer_;
  RadialRefinement radial_;
  MarginalizationPrior prior_;
  PixelSelector selector_;
  TraceSettings trace_settings_;
  std::vector<std::unique_ptr<WindowKeyframe>> window_;
  std::vector<std::unique_ptr<ImagePyramid>> pyramid_pool_;
  std::vector<float> energies_;  // scratch of adaptOutlierThreshold()
  std::mutex pool_mutex_;
  std::vector<SelectedPixel> selected_;
  int next_keyframe_id_ = 0;
  std::uint64_t next_point_id_ = 0;
  float min_activation_distance_ = 2.f;
  std::function<void(MarginalizedKeyframe&&)> on_leaving_;
  /// Corners detected on a keyframe leaving the window, for loop closure (at most kLoopCorners,
  /// Shi-Tomasi score >= kLoopCornerMinScore, i.e. a gradient of 3 grey levels per pixel).
  static constexpr int kLoopCorners = 400;
  static constexpr float kLoopCornerMinScore = 9.f;
  std::vector<Corner> loop_corners_;
};

}  // namespace ldsm
