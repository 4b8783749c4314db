#include "pipeline/slam_pipeline.h"

#include <algorithm>

#include "pipeline/map_persistence.h"
#include "pipeline/stage_settings.h"

namespace ldsm {
namespace {

int usableLevels(const PinholeIntrinsics& k, int wanted) {
  int levels = 1;
  while (levels < wanted && (k.width >> levels) >= 20 && (k.height >> levels) >= 15) ++levels;
  return levels;
}

bool photometryKnown(const FramePreprocessor& p, const Config& c) {
  return p.photometricallyCalibrated() && c.photometric.use_exposure;
}

std::unique_ptr<loop::LoopCloser> makeLoopCloser(const Config& config,
                                                 const PyramidCamera& camera) {
  if (!config.loop.enabled) return nullptr;
  const LevelCamera& c = camera[0];
  return std::make_unique<loop::LoopCloser>(
      config.loop, PinholeIntrinsics{c.fx, c.fy, c.cx, c.cy, c.width, c.height},
      /*inline_mode=*/stageMode(config) == concurrency::TaskMode::kInline);
}

}  // namespace

SlamPipeline::SlamPipeline(const Config& config, const GeometricCalibration& geometric,
                           const PhotometricCalibration& photometric)
    : preprocessor_(geometric, photometric, config.photometric),
      camera_(preprocessor_.output(),
              usableLevels(preprocessor_.output(), config.tracking.pyramid_levels)),
      // One spare pyramid in deterministic mode; threaded, as many as frames can queue for the
      // mapping thread and the one it works on (they come back together when it catches up).
      pyramids_(camera_[0].width, camera_[0].height, camera_.levels(),
                stageMode(config) == concurrency::TaskMode::kInline
                    ? 1
                    : static_cast<std::size_t>(std::max(config.system.mapping_queue, 0)) + 1),
      loop_closer_(makeLoopCloser(config, camera_)),
      mapping_(mappingStageSettings(config, photometryKnown(preprocessor_, config)), camera_,
               pyramids_, store_, events_, loop_closer_.get(),
               stageMode(config) == concurrency::TaskMode::kInline),
      tracking_(
          trackingStageSettings(config, camera_.levels(), photometryKnown(preprocessor_, config)),
          camera_, preprocessor_, pyramids_, store_, mapping_, events_) {
  map_calibration_ = mapCalibration(camera_[0], photometric, 0.0);
  localize_only_ = config.map.localize_only;
  store_.setFrameHistory(static_cast<std::size_t>(config.system.frameHistory()));
}

MapData SlamPipeline::exportMap() {
  MapCalibration calibration = map_calibration_;
  const std::shared_ptr<const MappingSnapshot> snapshot = mapping_.snapshot();
  calibration.radial_k = snapshot->radial_applied;
  calibration.focal_log_scale = snapshot->calibration_applied[kCalibFocal];
  calibration.cx_shift = snapshot->calibration_applied[kCalibCx];
  calibration.cy_shift = snapshot->calibration_applied[kCalibCy];
  MapExportScope scope;
  if (localize_only_) {
    scope.keyframes_below = loaded_keyframes_end_;
    scope.window = false;
    calibration = loaded_calibration_;
  }
  return ldsm::exportMap(store_, mapping_, loop_closer_.get(), camera_[0], calibration, scope);
}

void SlamPipeline::loadMap(const MapData& map, const std::string& where) {
  ldsm::importMap(map, map_calibration_, where, store_, mapping_, loop_closer_.get(), tracking_);
  loaded_keyframes_end_ = 0;
  for (const KeyframeRecord& r : map.keyframes)
    loaded_keyframes_end_ = std::max(loaded_keyframes_end_, r.id + 1);
  loaded_calibration_ = map.calibration;
}

SlamPipeline::~SlamPipeline() = default;

std::vector<MapPoint> SlamPipeline::mapPoints() const {
  const std::shared_ptr<const MappingSnapshot> s = mapping_.snapshot();
  std::vector<MapPoint> pts = store_.points(s->active_points.size());
  pts.insert(pts.end(), s->active_points.begin(), s->active_points.end());
  return pts;
}

void SlamPipeline::fillStats(SystemStats& stats) const {
  stats.keyframes = mapping_.keyframes();
  stats.initializations = tracking_.initializations();
  stats.tracking_losses = tracking_.losses();
  stats.initializer_frames = tracking_.initializerFrames();
  stats.initializer_busy_frames = tracking_.initializerBusyFrames();
  // Stage timings in the order preprocess, initialize, track, trace, mapping (with its parts
  // reuse and loop), total.
  const std::vector<StageTiming> t = tracking_.timings();
  const std::vector<StageTiming> m = mapping_.timings();
  stats.stages = {t[TrackingStage::kPreprocess], t[TrackingStage::kInitialize],
                  t[TrackingStage::kTrack],      m[MappingStage::kTrace],
                  m[MappingStage::kMapping],     m[MappingStage::kReuse],
                  m[MappingStage::kLoop],        t[TrackingStage::kTotal]};
  stats.loops = events_.loops();
  stats.loops_closed = events_.loopsClosed();
  stats.retired_frames = store_.retiredFrameCount();
  stats.lost_retired_frames = store_.lostRetiredFrameCount();
  const std::shared_ptr<const MappingSnapshot> s = mapping_.snapshot();
  stats.radial_estimate = s->radial_estimate;
  stats.radial_applied = s->radial_applied;
  stats.calibration = s->calibration;
  if (s->calibration_history) stats.calibration_history = *s->calibration_history;
  stats.reuse = s->reuse;
  stats.reuse.relocalization_attempts = tracking_.relocalizationAttempts();
  stats.reuse.relocalization_cross_checks = tracking_.crossChecks();
  stats.reuse.relocalization_answers_refused = tracking_.answersRefused();
  stats.reuse.relocalizations = tracking_.relocalizations();
  stats.map.keyframes = static_cast<std::int64_t>(store_.keyframeCount());
  stats.map.data_keyframes = static_cast<std::int64_t>(store_.dataKeyframeCount());
  stats.map.points = static_cast<std::int64_t>(store_.pointCount());
  stats.map.bytes = static_cast<std::int64_t>(store_.dataBytes());
  stats.map.bytes_per_keyframe =
      stats.map.data_keyframes > 0
          ? static_cast<double>(stats.map.bytes) / static_cast<double>(stats.map.data_keyframes)
          : 0.0;
  if (loop_closer_) {
    stats.map.pose_graph_vertices = loop_closer_->graphVertices();
    stats.map.pose_graph_edges = loop_closer_->graphEdges();
    stats.loop_dropped_keyframes = static_cast<std::int64_t>(loop_closer_->droppedKeyframes());
    stats.loop_unfinished_jobs = static_cast<std::int64_t>(loop_closer_->unfinishedJobs());
  }
  stats.mapping_backlog = static_cast<int>(mapping_.backlog());
}

}  // namespace ldsm
