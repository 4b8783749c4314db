// The public face of the engine: construct from a configuration and a calibration, submit frames,
// read back poses, keyframes and the map as values.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ldsm/camera/calibration.h"
#include "ldsm/config.h"
#include "ldsm/events.h"
#include "ldsm/image.h"
#include "ldsm/types.h"

namespace ldsm {

/// One input frame as a view of the caller's memory (8-bit grey, any stride). The system copies
/// what it needs before submit() returns.
struct FrameView {
  ImageView<const std::uint8_t> image;
  double timestamp = 0.0;                                         ///< seconds, increasing
  double exposure_ms = std::numeric_limits<double>::quiet_NaN();  ///< NaN when unknown
};

/// Timing of one processing stage over the run, milliseconds.
struct StageTiming {
  std::string stage;
  std::int64_t count = 0;
  double mean_ms = 0.0;
  double p50_ms = 0.0;
  double p99_ms = 0.0;
  double max_ms = 0.0;
};

/// What map reuse did during the run (config section reuse, docs/map-reuse.md).
struct ReuseStats {
  std::int64_t reactivations = 0;  ///< map keyframes brought back into the window
  std::int64_t deactivations = 0;  ///< taken back out (no longer fitting)
  std::int64_t candidates_checked = 0;
  std::int64_t rejected_geometry = 0;     ///< failed the viewing-angle or projection check
  std::int64_t rejected_features = 0;     ///< failed the ORB check
  std::int64_t rejected_photometric = 0;  ///< passed both; failed the direct check or the trial
  std::int64_t culled_keyframes = 0;      ///< kept as poses only (redundant with the map)
  std::int64_t map_points_seen = 0;       ///< inlier map points in new keyframes, summed
  std::int64_t relocalizations = 0;       ///< tracking resumed in the existing map after a loss
  std::int64_t relocalization_attempts = 0;
  std::int64_t new_maps = 0;  ///< maps started because relocalisation timed out
  /// Pose-graph corrections that map keyframes brought back into the window triggered (the
  /// drift a revisit revealed, spread over the keyframes in between).
  std::int64_t map_corrections = 0;
  std::int64_t merges = 0;  ///< maps merged into the current one (a loop connected them)
  /// Times a new window was started from the map because map keyframes agreed the window had
  /// drifted beyond its optimisation's reach (docs/map-reuse.md, "Re-anchoring a window that
  /// drifted off the map").
  std::int64_t window_reanchors = 0;
  /// Answers of the map checked against its other keyframes before a new window would be built
  /// on them (away from the kept window, or in a loaded map), and of those the ones refused (at
  /// least one neighbour aligned elsewhere and no fewer elsewhere than at the answer;
  /// docs/map-reuse.md, "Cross-checking the map's answer").
  std::int64_t relocalization_cross_checks = 0;
  std::int64_t relocalization_answers_refused = 0;
};

/// The size of the map: keyframes (created, and kept with their points and features), points,
/// and the memory the kept keyframes and points take.
struct MapStats {
  std::int64_t keyframes = 0;       ///< keyframe poses (every keyframe ever made)
  std::int64_t data_keyframes = 0;  ///< keyframes that keep points and features
  std::int64_t points = 0;          ///< points that left the window
  std::int64_t bytes = 0;           ///< kept keyframe data and points
  double bytes_per_keyframe = 0.0;  ///< bytes / data_keyframes
  /// Loop closure's Sim(3) pose graph (0 without loop closure): keyframes without map data leave
  /// it (loop.pose_graph_recent_keyframes), so it grows with the map, not with time.
  std::int64_t pose_graph_vertices = 0;
  std::int64_t pose_graph_edges = 0;
};

/// The online calibration refinement (config section calibration): the rectified pinhole the
/// engine works with and the correction it estimates. Parameters not refined stay at the
/// configured camera (estimate 0, sigma 0).
struct CalibrationStats {
  PinholeIntrinsics configured;  ///< the rectified pinhole of the calibration given
  PinholeIntrinsics applied;     ///< with the focal and principal point corrections applied
  double radial_applied = 0.0;   ///< residual radial k applied (see radial_estimate)
  /// The estimate, applied or not (each part is applied only outside its dead band):
  double radial_estimate = 0.0;
  double focal_scale_estimate = 1.0;  ///< fx, fy times this
  double cx_shift_estimate = 0.0;     ///< pixels
  double cy_shift_estimate = 0.0;     ///< pixels
  /// 1-sigma of the estimates from the fused window curvatures (relative: the curvatures are
  /// energies in grey levels squared; compare between parameters and runs, not as metres).
  double radial_sigma = 0.0, focal_scale_sigma = 0.0, cx_sigma = 0.0, cy_sigma = 0.0;
  /// The same, realistic: the formal sigmas scaled by the window overlap and by how far the
  /// windows' estimates actually scatter in units of their formal sigmas (they are 10-60x too
  /// small alone); what the significance test of the config section calibration uses.
  double realistic_radial_sigma = 0.0, realistic_focal_scale_sigma = 0.0;
  double realistic_cx_sigma = 0.0, realistic_cy_sigma = 0.0;
  int windows = 0;  ///< window estimates fused
};

/// The calibration refinement after one more window estimate was fused: how the estimate,
/// its uncertainty and the applied camera evolved over a run.
struct CalibrationSample {
  int windows = 0;                ///< window estimates fused so far
  std::int64_t frame_index = -1;  ///< the newest keyframe's frame
  double timestamp = 0.0;         ///< its time, seconds
  double radial_estimate = 0.0, focal_scale_estimate = 1.0;
  double cx_shift_estimate = 0.0, cy_shift_estimate = 0.0;  ///< pixels
  double radial_sigma = 0.0, focal_scale_sigma = 0.0, cx_sigma = 0.0, cy_sigma = 0.0;
  /// The same uncertainties made realistic (CalibrationStats::realistic_radial_sigma).
  double realistic_radial_sigma = 0.0, realistic_focal_scale_sigma = 0.0;
  double realistic_cx_sigma = 0.0, realistic_cy_sigma = 0.0;
  double radial_applied = 0.0;
  PinholeIntrinsics applied;  ///< the pinhole the window works with from then on
};

struct SystemStats {
  std::int64_t frames = 0;
  std::int64_t tracked_frames = 0;
  std::int64_t keyframes = 0;
  std::int64_t initializations = 0;  ///< times the map was (re)initialised
  std::int64_t tracking_losses = 0;
  std::int64_t rejected_frames = 0;  ///< frames refused as bad input (size, timestamp, content)
  /// Frames given to the initializer (stage "initialize" counts those it finished), and, in live
  /// mode, those that came while it was still busy with an earlier frame and so went without it
  /// (no pose, as every frame before a map exists). Many of those mean that the initializer sees
  /// frames far apart: the machine is slow for the camera's rate.
  std::int64_t initializer_frames = 0;
  std::int64_t initializer_busy_frames = 0;
  std::vector<StageTiming> stages;
  /// Loops closed, in order: the newest kMaxLoopEvents (loops_closed counts them all).
  std::vector<LoopClosureEvent> loops;
  std::int64_t loops_closed = 0;
  static constexpr int kMaxLoopEvents = 1024;
  /// Loop closure's keyframes not indexed (its queue was full, threaded mode, or it had been
  /// stopped), and its jobs abandoned by an end of run (finish, saveMap) that outlasted
  /// loop.finish_timeout_s; after such a timeout loop closure stays off for the session.
  std::int64_t loop_dropped_keyframes = 0;
  std::int64_t loop_unfinished_jobs = 0;
  /// Frames whose poses left memory (system.frame_history; System::takeRetiredFrames()), and of
  /// those dropped because the application did not take them in time.
  std::int64_t retired_frames = 0;
  std::int64_t lost_retired_frames = 0;
  /// Online calibration refinement (config section calibration): the residual radial
  /// distortion k of the rectified images, x_image = x (1 + k |x|^2) in the rectified camera's
  /// normalized coordinates, as estimated and as applied (0 while inside the dead band).
  double radial_estimate = 0.0;
  double radial_applied = 0.0;
  /// The whole online calibration refinement (radial k, focal scale, principal point).
  CalibrationStats calibration;
  /// Its history, oldest first: one sample per fused window until kMaxCalibrationSamples are
  /// held, then every second one is dropped and only every second window recorded (and so on),
  /// so that the history of a long run stays bounded and spans it evenly.
  std::vector<CalibrationSample> calibration_history;
  static constexpr int kMaxCalibrationSamples = 256;
  ReuseStats reuse;
  MapStats map;

  // The frame pipeline between submit() and tracking. `frames` above counts the frames the
  // tracking received; submitted_frames == frames + dropped_frames once finish() returned.
  std::int64_t submitted_frames = 0;  ///< frames accepted by submit() (right size)
  std::int64_t dropped_frames = 0;    ///< live mode: oldest queued frames dropped (tracking behind)
  int queue_capacity = 0;             ///< frames the tracking queue holds (0: deterministic mode)
  int max_queue_depth = 0;            ///< frames waiting for tracking, sampled after each submit()
  double mean_queue_depth = 0.0;
  /// Latency per stage, measured from submit(): "queue_wait" (until tracking starts on the
  /// frame), "submit_to_processed" (until tracking is done with it, every frame that reached the
  /// odometry: also those of the initialisation and those without a pose) and
  /// "submit_to_tracked" (until its pose is known and published: the frames with a pose). In
  /// deterministic mode no "queue_wait" (the others are the time submit() took).
  std::vector<StageTiming> latency;
  /// Frames tracked but not yet integrated by the mapping thread, sampled after each tracked
  /// frame (0 in deterministic mode), and at the time of the call.
  int max_mapping_backlog = 0;
  double mean_mapping_backlog = 0.0;
  int mapping_backlog = 0;
};

/// The newest tracked frame as the tracker saw it, for viewers: the rectified, photometrically
/// corrected image at half resolution (pyramid level 1) and the pixels (at that resolution) where
/// the reference keyframe's full-resolution points fall with the frame's tracked pose.
struct TrackedImage {
  std::int64_t frame_index = -1;
  double timestamp = 0.0;
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;     ///< width * height grey values, row by row
  std::vector<Eigen::Vector2f> points;  ///< tracked points inside the image
};

class System {
 public:
  /// Validates the configuration and the calibration (ConfigError / InputError naming the field).
  System(const Config& config, const GeometricCalibration& geometric,
         const PhotometricCalibration& photometric = {});
  /// Starts from a saved map (the bytes of a map file, docs/map-file.md; e.g.
  /// drivers::readMapFile()): the first frames are looked for in it and tracking goes on in its
  /// frame and scale; when they are not found for reuse.relocalization_timeout_s, a new map
  /// starts and is merged into the loaded one once a loop connects them (StampedPose::map says
  /// which poses are not yet in its frame). With map.localize_only the map is never changed.
  /// Throws InputError naming `where` and the part of the file that is wrong (truncated,
  /// corrupted, another format version, made with another camera or image size) and
  /// ConfigError when loop closure or reuse is off.
  System(const Config& config, const GeometricCalibration& geometric,
         const PhotometricCalibration& photometric, const std::vector<std::uint8_t>& map,
         const std::string& where = "map");
  ~System();
  System(const System&) = delete;
  System& operator=(const System&) = delete;

  /// Receives events; may be null. Set before the first submit().
  void setListener(SystemListener* listener);

  /// Processes (deterministic mode) or queues (threaded mode) one frame. A frame of the wrong
  /// size throws InputError; a frame with a NaN/zero exposure, a duplicated or backwards
  /// timestamp, or an all-black/saturated image is rejected with a warning and counted.
  /// Threaded mode copies the frame into a buffer of a pool allocated at start-up and queues it
  /// for the tracking thread; when the queue is full, submit() waits (offline) or drops the
  /// oldest queued frame (system.live). Call it from one thread.
  void submit(const FrameView& frame);

  /// Waits until every submitted frame is processed and the last optimisation has finished.
  void finish();

  /// The status after the last processed frame (lock-free).
  TrackingStatus status() const;
  /// The pose of the most recently tracked frame (camera-to-world, as tracked: before the
  /// window optimisation refines it), or nothing before the first pose. Lock-free and
  /// wait-free (a triple buffer written by the tracking thread): call it from one thread at a
  /// time, e.g. the application's control loop.
  std::optional<StampedPose> latestPose() const;
  /// From now on the tracking publishes each tracked frame's image (half resolution) and tracked
  /// points for latestTrackedImage(): one image copy per frame, nothing allocated after the
  /// first. Off by default. Call it before the first submit().
  void publishTrackedImages();
  /// The newest tracked image with its tracked points, or nothing before the first tracked frame
  /// or without publishTrackedImages(). Lock-free like latestPose() (a triple buffer
  /// the tracking thread writes without allocating): call it from one thread at a time.
  std::optional<TrackedImage> latestTrackedImage() const;
  /// The final estimate of every processed frame that has a pose (camera-to-world, TUM order)
  /// and is still held in memory: every frame, unless system.frame_history bounds them (by
  /// default in live mode), then the newest ones; takeRetiredFrames() hands out the older ones.
  Trajectory trajectory() const;
  /// The poses of frames that left memory (system.frame_history) since the last call, oldest
  /// first, as estimated when they left (later loop corrections do not move them);
  /// trajectory() continues them. Call it now and then (every few seconds) in a long run and
  /// write what it returns: at most 4 x 4096 frames wait, older ones are dropped and counted
  /// (SystemStats::lost_retired_frames). Never waits for the optimiser.
  Trajectory takeRetiredFrames();
  /// The keyframes' poses (final estimates).
  Trajectory keyframeTrajectory() const;
  /// Every point of the map (active and marginalised), world coordinates.
  std::vector<MapPoint> mapPoints() const;
  SystemStats stats() const;
  /// The map as a map file's bytes (docs/map-file.md; write them with drivers::writeMapFile()):
  /// the keyframes, their points and features, the pose graph, the vocabulary and the
  /// calibration, in the frame poses are reported in (the first map's; maps not merged into it
  /// are left out). Waits like finish() for every submitted frame first.
  std::vector<std::uint8_t> saveMap();
  /// The ideal pinhole the engine works in (after rectification).
  PinholeIntrinsics rectifiedCamera() const;

 private:
  void start(const Config& config, const GeometricCalibration& geometric,
             const PhotometricCalibration& photometric);
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ldsm
