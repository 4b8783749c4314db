#include "pipeline/stage_settings.h"

#include <algorithm>
#include <thread>

namespace ldsm {
namespace {

WindowOptimizerSettings optimizerSettings(const Config& c, bool photometry_known) {
  WindowOptimizerSettings s;
  s.max_iterations = c.window.max_iterations;
  s.min_relative_decrease = c.window.min_relative_decrease;
  const double w = photometry_known ? c.photometric.affine_prior_weight_known
                                    : c.photometric.affine_prior_weight_unknown;
  s.affine_prior_a = w;
  s.affine_prior_b = w;
  s.residual.huber_threshold = static_cast<float>(c.tracking.huber_threshold);
  const float th = static_cast<float>(c.window.outlier_threshold);
  s.residual.outlier_energy = th * th * kPatternSize;
  s.estimate_calibration = {c.calibration.refine_radial, c.calibration.refine_focal,
                            c.calibration.refine_principal_point,
                            c.calibration.refine_principal_point};
  s.reactivated_weight = c.reuse.reactivated_pose_weight;
  return s;
}

}  // namespace

concurrency::TaskMode stageMode(const Config& config) {
  return config.system.deterministic ? concurrency::TaskMode::kInline
                                     : concurrency::TaskMode::kThreaded;
}

namespace {

/// system.parallel_threads resolved for a stage that leaves `reserved` cores to the others.
int resolvedThreads(const Config& config, int reserved) {
  if (config.system.parallel_threads > 0) return config.system.parallel_threads;
  if (config.system.deterministic) return 1;
  const int cores = static_cast<int>(std::thread::hardware_concurrency());
  return std::clamp(cores - reserved, 1, SystemConfig::kMaxAutomaticParallelThreads);
}

}  // namespace

int parallelThreads(const Config& config) {
  return resolvedThreads(config, 0);
}

int mappingParallelThreads(const Config& config) {
  return resolvedThreads(config, 1);  // tracking keeps a core of its own
}

CoarseTrackerSettings coarseTrackerSettings(const Config& config, bool exposures_known) {
  CoarseTrackerSettings s;
  s.huber_threshold = static_cast<float>(config.tracking.huber_threshold);
  const int it = config.tracking.max_iterations_per_level;
  for (int l = 0; l < kMaxPyramidLevels; ++l)
    s.max_iterations[l] = l == 0 ? it : (l == 1 ? 2 : 5) * it;
  const double prior = exposures_known ? config.photometric.affine_prior_weight_known
                                       : config.photometric.affine_prior_weight_unknown;
  s.affine_prior_weight_a = prior;
  s.affine_prior_weight_b = prior;
  return s;
}

CoarseInitializerSettings coarseInitializerSettings(const Config& config, int max_levels,
                                                    bool exposures_known) {
  CoarseInitializerSettings s;
  s.max_levels = std::clamp(max_levels, 1, kMaxPyramidLevels);
  s.huber_threshold = static_cast<float>(config.tracking.huber_threshold);
  s.selection = config.points;
  s.selector_density = static_cast<float>(config.initializer.point_density);
  s.min_parallax_flow = static_cast<float>(config.initializer.min_parallax_px);
  s.min_rotation_free_parallax =
      static_cast<float>(config.initializer.min_rotation_free_parallax_px);
  s.confirm_frames = config.initializer.confirm_frames;
  if (exposures_known) {
    s.affine_prior_weight_a = CoarseInitializerSettings::kAffinePriorKnownA;
    s.affine_prior_weight_b = CoarseInitializerSettings::kAffinePriorKnownB;
  }
  return s;
}

FrameTrackerSettings frameTrackerSettings(const Config& config, bool exposures_known) {
  return {config.keyframes, coarseTrackerSettings(config, exposures_known),
          config.tracking.max_rmse_growth};
}

MapperSettings mapperSettings(const Config& config, bool photometry_known) {
  MapperSettings s;
  s.window = config.window;
  s.points = config.points;
  s.calibration = config.calibration;
  s.optimizer = optimizerSettings(config, photometry_known);
  s.trace_huber_threshold = static_cast<float>(config.tracking.huber_threshold);
  s.trace_outlier_threshold = static_cast<float>(config.window.outlier_threshold);
  return s;
}

TrackingStageSettings trackingStageSettings(const Config& config, int levels,
                                            bool photometry_known) {
  TrackingStageSettings s;
  s.initializer = coarseInitializerSettings(config, levels, photometry_known);
  s.initializer_hypotheses = config.initializer.hypotheses;
  s.tracker = frameTrackerSettings(config, photometry_known);
  s.reuse = config.reuse;
  s.localize_only = config.map.localize_only;
  s.wait_for_keyframes = !config.system.live && !config.system.deterministic;
  s.parallel_threads = parallelThreads(config);
  s.async_initialization = config.system.live && !config.system.deterministic;
  return s;
}

MappingStageSettings mappingStageSettings(const Config& config, bool photometry_known) {
  MappingStageSettings s;
  s.mapper = mapperSettings(config, photometry_known);
  s.tracker = coarseTrackerSettings(config, photometry_known);
  s.reuse = config.reuse;
  s.queue_capacity = config.system.mapping_queue;
  s.loop_corners = config.loop.corners_per_keyframe;
  s.loop_corner_min_score = static_cast<float>(config.loop.corner_min_score);
  s.localize_only = config.map.localize_only;
  s.parallel_threads = mappingParallelThreads(config);
  return s;
}

}  // namespace ldsm
