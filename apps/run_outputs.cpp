#include "run_outputs.h"

#include <sys/resource.h>

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "ldsm/calib/refined_camera.h"
#include "ldsm/camera/camera_model.h"
#include "ldsm/drivers/atomic_file.h"
#include "ldsm/drivers/json_writer.h"
#include "ldsm/drivers/machine_info.h"
#include "ldsm/drivers/ply_writer.h"
#include "ldsm/drivers/trajectory_io.h"
#include "ldsm/error.h"

namespace ldsm::app {

double peakRssMb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // KB on Linux
}

namespace {

/// {"stage": {"count", "mean_ms", "p50_ms", "p99_ms", "max_ms"}, ...}
void writeTimings(drivers::JsonWriter& j, const std::vector<StageTiming>& timings) {
  j.beginObject();
  for (const StageTiming& t : timings) {
    j.key(t.stage).beginObject();
    j.key("count").value(t.count);
    j.key("mean_ms").value(t.mean_ms);
    j.key("p50_ms").value(t.p50_ms);
    j.key("p99_ms").value(t.p99_ms);
    j.key("max_ms").value(t.max_ms);
    j.endObject();
  }
  j.endObject();
}

/// "history": [{"windows", "frame", "t", "estimate": [k, focal_scale, cx_shift, cy_shift],
/// "sigma": [...], "sigma_realistic": [...], "applied": [k, fx, fy, cx, cy]}, ...], oldest first.
void writeCalibrationHistory(drivers::JsonWriter& j, const std::vector<CalibrationSample>& h) {
  j.key("history").beginArray();
  for (const CalibrationSample& c : h) {
    j.beginObject();
    j.key("windows").value(static_cast<std::int64_t>(c.windows));
    j.key("frame").value(c.frame_index);
    j.key("t").value(c.timestamp);
    j.key("estimate").beginArray();
    for (const double v :
         {c.radial_estimate, c.focal_scale_estimate, c.cx_shift_estimate, c.cy_shift_estimate})
      j.value(v);
    j.endArray();
    j.key("sigma").beginArray();
    for (const double v : {c.radial_sigma, c.focal_scale_sigma, c.cx_sigma, c.cy_sigma}) j.value(v);
    j.endArray();
    j.key("sigma_realistic").beginArray();
    for (const double v : {c.realistic_radial_sigma, c.realistic_focal_scale_sigma,
                           c.realistic_cx_sigma, c.realistic_cy_sigma})
      j.value(v);
    j.endArray();
    j.key("applied").beginArray();
    for (const double v :
         {c.radial_applied, c.applied.fx, c.applied.fy, c.applied.cx, c.applied.cy})
      j.value(v);
    j.endArray();
    j.endObject();
  }
  j.endArray();
}

/// Runs one file's writer; a failure is collected, not thrown, so the other files still get
/// their chance (a full disk may take one file and leave room for a smaller one).
template <typename Write>
void attempt(std::vector<std::string>& errors, Write&& write) {
  try {
    write();
  } catch (const Error& e) {
    errors.push_back(e.what());
  }
}

void throwIfAny(const std::vector<std::string>& errors) {
  if (errors.empty()) return;
  std::string what = errors.front();
  for (std::size_t i = 1; i < errors.size(); ++i) what += "; " + errors[i];
  throw Error(what);
}

std::string outputBase(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw Error(dir + ": cannot create the output folder: " + ec.message());
  return (std::filesystem::path(dir) / "").string();
}

void writeTrajectories(const std::string& base, const System& system, const Trajectory& frames,
                       std::vector<std::string>& errors) {
  attempt(errors, [&] { drivers::writeTumTrajectory(base + "trajectory.txt", frames); });
  attempt(errors, [&] {
    drivers::writeTumTrajectory(base + "keyframes.txt", system.keyframeTrajectory());
  });
}

}  // namespace

void writeTrajectoriesSoFar(const std::string& dir, const System& system,
                            const Trajectory& frames) {
  const std::string base = outputBase(dir);
  std::vector<std::string> errors;
  writeTrajectories(base, system, frames, errors);
  throwIfAny(errors);
}

void writeRunOutputs(const std::string& dir, const System& system, const Trajectory& frames,
                     const RunSummary& summary) {
  const std::string base = outputBase(dir);
  std::vector<std::string> errors;
  writeTrajectories(base, system, frames, errors);

  const std::vector<MapPoint> points = system.mapPoints();
  std::vector<Eigen::Vector3f> xyz;
  std::vector<std::array<std::uint8_t, 3>> colours;
  xyz.reserve(points.size());
  for (const MapPoint& p : points) {
    const Eigen::Vector3f pf = p.position.cast<float>();
    // Points of a map not merged into the first one are in another frame: not in the cloud.
    if (!pf.allFinite() || p.map != 0) continue;
    xyz.push_back(pf);
    const auto g = static_cast<std::uint8_t>(std::clamp(p.intensity, 0.f, 255.f));
    colours.push_back(p.is_corner ? std::array<std::uint8_t, 3>{255, 64, 0}
                                  : std::array<std::uint8_t, 3>{g, g, g});
  }
  attempt(errors, [&] { drivers::writePly(base + "points.ply", xyz, colours); });

  const SystemStats s = system.stats();
  std::optional<calib::RefinedCameraFit> camera;
  if (summary.calibration.input.width > 0) {
    attempt(errors, [&] {
      try {
        camera = calib::refitCalibration(summary.calibration, s.calibration, s.calibration_history);
      } catch (const Error& e) {
        throw Error(base + "camera.txt, " + base + "camchain.yaml: not written: " + e.what());
      }
    });
  }
  if (camera) {
    const auto write_camera = [&](const std::string& name, auto format) {
      std::error_code ec;
      if (std::filesystem::equivalent(base + name, summary.calibration_source, ec)) {
        // Never replace the calibration the run read (an output folder that is the dataset's).
        errors.push_back(base + name + ": not written: it is the calibration this run read");
        return;
      }
      attempt(errors, [&] {
        drivers::writeFileAtomically(base + name, format(*camera, summary.calibration_source));
      });
    };
    write_camera("camera.txt", calib::formatRefinedDsoCameraFile);
    write_camera("camchain.yaml", calib::formatRefinedKalibrYaml);
  }
  drivers::JsonWriter j;
  j.beginObject();
  j.key("dataset").value(summary.dataset);
  j.key("status").value(summary.status);
  j.key("tracking_status").value(toString(system.status()));
  j.key("frames").value(s.frames);
  j.key("tracked_frames").value(s.tracked_frames);
  j.key("rejected_frames").value(s.rejected_frames);
  j.key("keyframes").value(s.keyframes);
  j.key("initializations").value(s.initializations);
  j.key("initializer_frames").value(s.initializer_frames);
  j.key("initializer_busy_frames").value(s.initializer_busy_frames);
  j.key("tracking_losses").value(s.tracking_losses);
  j.key("map_points").value(static_cast<std::int64_t>(xyz.size()));
  j.key("wall_seconds").value(summary.wall_seconds);
  j.key("ms_per_frame").value(summary.ms_per_frame);
  j.key("peak_rss_mb").value(summary.peak_rss_mb);
  // Figures from different machines are only comparable with this (docs/determinism.md).
  const drivers::MachineInfo machine = drivers::describeMachine();
  j.key("machine").beginObject();
  j.key("cpu").value(machine.cpu_model);
  j.key("simd").value(machine.build.simd);
  j.key("opencv").value(machine.build.opencv_version);
  j.key("opencv_optimized").value(machine.build.opencv_optimized);
  j.key("opencv_cpu_features").value(machine.build.opencv_cpu_features);
  j.key("blas").value(machine.blas_library);
  j.key("openblas_coretype").value(machine.openblas_coretype);
  j.endObject();
  j.key("radial_correction").beginObject();
  j.key("estimate").value(s.radial_estimate);
  j.key("applied").value(s.radial_applied);
  j.endObject();
  const CalibrationStats& c = s.calibration;
  j.key("calibration").beginObject();
  j.key("windows").value(c.windows);
  const auto pinhole = [&j](const char* key, const PinholeIntrinsics& k) {
    j.key(key).beginObject();
    j.key("fx").value(k.fx);
    j.key("fy").value(k.fy);
    j.key("cx").value(k.cx);
    j.key("cy").value(k.cy);
    j.key("width").value(k.width);
    j.key("height").value(k.height);
    j.endObject();
  };
  pinhole("configured", c.configured);
  pinhole("applied", c.applied);
  j.key("radial_applied").value(c.radial_applied);
  // Four figures under their names, one object: the parameter estimates and their sigmas in the
  // window's units (k, focal scale, cx/cy shift) and the written camera's sigmas in pixels.
  const auto four = [&j](const char* key, const char* const(&names)[4],
                         const std::array<double, 4>& values) {
    j.key(key).beginObject();
    for (std::size_t i = 0; i < values.size(); ++i) j.key(names[i]).value(values[i]);
    j.endObject();
  };
  static const char* const kParameters[4] = {"radial_k", "focal_scale", "cx_shift", "cy_shift"};
  static const char* const kPixels[4] = {"fx", "fy", "cx", "cy"};
  four("estimate", kParameters,
       {c.radial_estimate, c.focal_scale_estimate, c.cx_shift_estimate, c.cy_shift_estimate});
  four("sigma", kParameters, {c.radial_sigma, c.focal_scale_sigma, c.cx_sigma, c.cy_sigma});
  four("sigma_realistic", kParameters,
       {c.realistic_radial_sigma, c.realistic_focal_scale_sigma, c.realistic_cx_sigma,
        c.realistic_cy_sigma});
  if (camera) {
    four("sigma_px", kPixels,
         {camera->sigma_fx, camera->sigma_fy, camera->sigma_cx, camera->sigma_cy});
    four("sigma_px_realistic", kPixels,
         {camera->realistic_sigma_fx, camera->realistic_sigma_fy, camera->realistic_sigma_cx,
          camera->realistic_sigma_cy});
    j.key("spread").beginObject();
    j.key("windows").value(camera->spread_windows);
    j.key("radial_k").value(camera->spread_k);
    j.key("fx").value(camera->spread_fx);
    j.key("fy").value(camera->spread_fy);
    j.key("cx").value(camera->spread_cx);
    j.key("cy").value(camera->spread_cy);
    j.endObject();
    j.key("written").beginObject();
    j.key("model").value(cameraModelName(camera->calibration.input.model));
    j.key("changed").value(camera->changed);
    j.key("fit_rms_px").value(camera->rms_px);
    j.key("fit_max_px").value(camera->max_px);
    j.endObject();
  }
  writeCalibrationHistory(j, s.calibration_history);
  j.endObject();
  j.key("reuse").beginObject();
  j.key("reactivations").value(s.reuse.reactivations);
  j.key("deactivations").value(s.reuse.deactivations);
  j.key("candidates_checked").value(s.reuse.candidates_checked);
  j.key("rejected_geometry").value(s.reuse.rejected_geometry);
  j.key("rejected_features").value(s.reuse.rejected_features);
  j.key("rejected_photometric").value(s.reuse.rejected_photometric);
  j.key("culled_keyframes").value(s.reuse.culled_keyframes);
  j.key("map_points_seen").value(s.reuse.map_points_seen);
  j.key("relocalizations").value(s.reuse.relocalizations);
  j.key("relocalization_attempts").value(s.reuse.relocalization_attempts);
  j.key("new_maps").value(s.reuse.new_maps);
  j.key("map_corrections").value(s.reuse.map_corrections);
  j.key("merges").value(s.reuse.merges);
  j.key("window_reanchors").value(s.reuse.window_reanchors);
  j.key("relocalization_cross_checks").value(s.reuse.relocalization_cross_checks);
  j.key("relocalization_answers_refused").value(s.reuse.relocalization_answers_refused);
  j.endObject();
  j.key("map").beginObject();
  j.key("keyframes").value(s.map.keyframes);
  j.key("data_keyframes").value(s.map.data_keyframes);
  j.key("points").value(s.map.points);
  j.key("bytes").value(s.map.bytes);
  j.key("bytes_per_keyframe").value(s.map.bytes_per_keyframe);
  j.key("pose_graph_vertices").value(s.map.pose_graph_vertices);
  j.key("pose_graph_edges").value(s.map.pose_graph_edges);
  // system.frame_history: frame poses that left memory (written to trajectory.txt all the same)
  j.key("retired_frames").value(s.retired_frames);
  j.key("lost_retired_frames").value(s.lost_retired_frames);
  j.endObject();
  j.key("stages");
  writeTimings(j, s.stages);
  j.key("pipeline").beginObject();
  j.key("mode").value(summary.mode);
  j.key("submitted_frames").value(s.submitted_frames);
  j.key("received_frames").value(s.frames);
  j.key("dropped_frames").value(s.dropped_frames);
  j.key("queue_capacity").value(static_cast<std::int64_t>(s.queue_capacity));
  j.key("max_queue_depth").value(static_cast<std::int64_t>(s.max_queue_depth));
  j.key("mean_queue_depth").value(s.mean_queue_depth);
  j.key("max_mapping_backlog").value(static_cast<std::int64_t>(s.max_mapping_backlog));
  j.key("mean_mapping_backlog").value(s.mean_mapping_backlog);
  j.key("latency");
  writeTimings(j, s.latency);
  if (summary.realtime_speed > 0.0) {
    j.key("realtime_speed").value(summary.realtime_speed);
    j.key("max_source_lateness_ms").value(summary.max_source_lateness_ms);
  }
  j.endObject();
  j.key("loop_dropped_keyframes").value(s.loop_dropped_keyframes);
  j.key("loop_unfinished_jobs").value(s.loop_unfinished_jobs);
  j.key("loops_closed").value(s.loops_closed);  // "loops" lists the newest kMaxLoopEvents
  j.key("loops").beginArray();
  for (const LoopClosureEvent& l : s.loops) {
    j.beginObject();
    j.key("keyframe").value(static_cast<std::int64_t>(l.current_keyframe_id));
    j.key("matched_keyframe").value(static_cast<std::int64_t>(l.matched_keyframe_id));
    j.key("inliers").value(static_cast<std::int64_t>(l.inliers));
    j.key("scale").value(l.scale);
    j.key("time_ms").value(l.time_ms);
    j.key("drift_chi2").value(l.drift_chi2);
    j.key("corrected_keyframes").value(static_cast<std::int64_t>(l.corrected_keyframes));
    j.endObject();
  }
  j.endArray();
  if (summary.ate) {
    j.key("ate").beginObject();
    j.key("rmse_m").value(summary.ate->rmse);
    j.key("matched_poses").value(static_cast<std::int64_t>(summary.ate->matched));
    j.key("gt_path_length_m").value(summary.ate->gt_path_length);
    j.key("scale").value(summary.ate->sim3_scale);
    j.endObject();
  } else {
    j.key("ate").null();
  }
  j.endObject();
  attempt(errors, [&] { drivers::writeFileAtomically(base + "stats.json", j.str() + "\n"); });
  throwIfAny(errors);
}

}  // namespace ldsm::app
