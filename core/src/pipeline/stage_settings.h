// From the configuration tree to the settings of the stages and of what they own: the one place
// where the engine reads `Config` (besides System, which reads the system section). Frontend,
// backend, loop and reuse take only their settings struct or their own configuration section;
// the derived values (per-level iteration counts, affine priors for known or unknown exposures,
// the window optimiser's outlier energy) are worked out here.
#pragma once

#include "backend/mapper.h"
#include "concurrency/background_task.h"
#include "frontend/coarse_initializer_settings.h"
#include "frontend/coarse_tracker.h"
#include "frontend/frame_tracker.h"
#include "ldsm/config.h"
#include "pipeline/mapping_stage.h"
#include "pipeline/tracking_stage.h"

namespace ldsm {

/// The one choice of the mode, for every stage (input, mapping, loop closure): inline on the
/// caller's thread (system.deterministic) or each on a thread of its own.
concurrency::TaskMode stageMode(const Config& config);
/// system.parallel_threads resolved (0: automatic) to a number of threads >= 1.
int parallelThreads(const Config& config);
/// The same for the mapping stage: automatic leaves one core to tracking.
int mappingParallelThreads(const Config& config);

/// tracking.huber_threshold, tracking.max_iterations_per_level (for level 0; level 1 gets twice
/// and coarser levels five times as many, as coarse levels are cheap and start furthest from the
/// solution) and the affine prior weight for known or unknown exposures.
CoarseTrackerSettings coarseTrackerSettings(const Config& config, bool exposures_known);

/// Defaults with the configured values: initializer.* (parallax thresholds, confirmation frames,
/// point density), points.* (the level-0 selection), tracking.huber_threshold, at most
/// `max_levels` pyramid levels, and strong affine priors when the frames' exposure times are
/// known (photometrically calibrated input).
CoarseInitializerSettings coarseInitializerSettings(const Config& config, int max_levels,
                                                    bool exposures_known);

/// keyframes.*, tracking.max_rmse_growth and the coarse tracker's settings.
FrameTrackerSettings frameTrackerSettings(const Config& config, bool exposures_known);

/// `photometry_known`: response, vignette and exposure times are known, so affine brightness is
/// held near zero by the strong prior (photometric.affine_prior_weight_known).
MapperSettings mapperSettings(const Config& config, bool photometry_known);

/// `levels`: the pyramid levels the camera uses.
TrackingStageSettings trackingStageSettings(const Config& config, int levels,
                                            bool photometry_known);

MappingStageSettings mappingStageSettings(const Config& config, bool photometry_known);

}  // namespace ldsm
