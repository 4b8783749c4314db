// `ldsm run`: SLAM on a recorded sequence (offline, or replayed in real time through the live
// pipeline with --realtime) or on a V4L2 camera (--live), with a progress line, writing the
// trajectory, the keyframes, the map and statistics; evaluates against ground truth when the
// dataset has one. Ctrl-C, a device error or a bad file stop the run and keep what was computed.
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>
#include <thread>

#include "commands.h"
#include "interrupt.h"
#include "ldsm/calib/calibration_loader.h"
#include "ldsm/calib/photometric_files.h"
#include "ldsm/calib/pinhole_guess.h"
#include "ldsm/drivers/config_yaml.h"
#include "ldsm/drivers/dataset_calibration.h"
#include "ldsm/drivers/dataset_description.h"
#include "ldsm/drivers/dataset_source.h"
#include "ldsm/drivers/map_file_io.h"
#include "ldsm/drivers/realtime_replay_source.h"
#include "ldsm/drivers/trajectory_io.h"
#include "ldsm/drivers/trajectory_spill.h"
#include "ldsm/error.h"
#include "ldsm/eval/ate.h"
#include "ldsm/system.h"
#include "run_outputs.h"
#include "viewer/run_viewer.h"
#if defined(LDSM_HAVE_V4L2)
#include "ldsm/drivers/v4l2_source.h"
#endif

namespace ldsm::app {
namespace {

struct RunOptions {
  std::string dataset;
  std::string format = "auto";
  std::string calib;
  double fov_deg = 0.0;  ///< --fov: start from a pinhole guess (0: not given)
  std::string config;
  std::string out = "ldsm_out";
  bool deterministic = false;
  bool no_loop = false;
  bool no_reuse = false;
  std::int64_t max_frames = 0;
  bool no_eval = false;
  double flush_every_s = 30.0;  ///< trajectory.txt and keyframes.txt rewritten this often (0: off)
  // Real-time replay of the dataset through the live pipeline.
  bool realtime = false;
  double speed = 1.0;
  // Live camera.
  std::string live;  ///< V4L2 device
  std::string pcalib;
  std::string vignette;
  int width = 0;
  int height = 0;
  double fps = 0.0;
  std::string pixel_formats;
  double exposure_ms = 0.0;
  double gain = -1.0;
  bool lock_exposure = false;
  int timeout_ms = 2000;
  // Maps across sessions (docs/map-file.md).
  std::string load_map;
  std::string save_map;
  bool localize_only = false;
  // Browser viewer (docs/viewer.md).
  std::string serve;  ///< "[ADDR:]PORT"; empty: no viewer
  bool serve_wait = false;
  std::string web_root;
};

/// Where the frames come from, with the calibration that goes with them.
struct RunInput {
  std::unique_ptr<drivers::FrameSource> source;
  GeometricCalibration geometric;
  PhotometricCalibration photometric;
  std::string name;  ///< dataset path or device
  std::string geometric_source;
  std::string photometric_source = "none";
  std::int64_t frame_count = -1;  ///< -1: unbounded (camera)
  std::optional<drivers::DatasetDescription> dataset;
  const drivers::RealtimeReplaySource* replay = nullptr;
};

/// Counts events for the progress line.
class ProgressListener : public SystemListener {
 public:
  void onKeyframe(const KeyframeEvent&) override { ++keyframes; }
  void onTrackingLost(const TrackingLostEvent& e) override {
    ++losses;
    spdlog::warn("tracking lost at frame {}: {}", e.frame_index, e.reason);
  }
  std::atomic<int> keyframes{0};
  std::atomic<int> losses{0};
};

std::optional<eval::AteResult> evaluate(const drivers::DatasetDescription& d,
                                        const Trajectory& est) {
  if (d.groundtruth_file.empty() || est.size() < 3) return std::nullopt;
  try {
    const Trajectory gt =
        drivers::readTrajectory(d.groundtruth_file, d.groundtruth_format, &d.timestamps);
    return eval::computeAte(gt, est);
  } catch (const Error& e) {
    spdlog::warn("no accuracy figure: {}", e.what());
    return std::nullopt;
  }
}

RunInput openDatasetInput(const RunOptions& o) {
  RunInput in;
  in.dataset = drivers::describeDataset(o.dataset, drivers::parseDatasetFormat(o.format));
  const drivers::DatasetCalibration calib =
      drivers::loadDatasetCalibration(*in.dataset, o.calib, o.fov_deg);
  in.geometric = calib.geometric;
  in.photometric = calib.photometric;
  in.geometric_source = calib.geometric_source;
  in.photometric_source = calib.photometric_source;
  in.name = o.dataset;
  in.frame_count = in.dataset->frame_count;
  in.source = drivers::openDataset(*in.dataset);
  if (o.realtime) {
    auto replay = std::make_unique<drivers::RealtimeReplaySource>(std::move(in.source), o.speed);
    in.replay = replay.get();
    in.source = std::move(replay);
  }
  return in;
}

#if defined(LDSM_HAVE_V4L2)
std::vector<drivers::V4l2PixelFormat> parsePixelFormats(const std::string& list) {
  std::vector<drivers::V4l2PixelFormat> formats;
  std::stringstream ss(list);
  std::string name;
  while (std::getline(ss, name, ','))
    if (!name.empty()) formats.push_back(drivers::parseV4l2PixelFormat(name));
  return formats;
}
#endif

RunInput openLiveInput(const RunOptions& o) {
  const bool guess = o.fov_deg != 0.0;
  if (o.calib.empty() && !guess)
    throw ConfigError(
        "run --live: give the camera's calibration with --calib FILE, or a guess of its "
        "horizontal field of view with --fov DEG");
  if (!o.calib.empty() && guess) throw ConfigError("run: give either --calib FILE or --fov DEG");
#if defined(LDSM_HAVE_V4L2)
  RunInput in;
  if (guess) {
    // Validated before the device is opened; the size is the device's unless told.
    in.geometric =
        calib::pinholeFromFieldOfView(std::max(o.width, 1), std::max(o.height, 1), o.fov_deg);
    in.geometric.input.width = o.width;
    in.geometric.input.height = o.height;
  } else {
    in.geometric = calib::loadGeometricCalibration(o.calib, o.width, o.height);
    in.geometric_source = o.calib;
  }
  const CameraIntrinsics& k = in.geometric.input;
  drivers::V4l2Options camera;
  camera.device = o.live;
  if (!o.pixel_formats.empty()) camera.formats = parsePixelFormats(o.pixel_formats);
  camera.width = o.width > 0 ? o.width : k.width;  // the calibrated size unless told otherwise
  camera.height = o.height > 0 ? o.height : k.height;
  camera.fps = o.fps;
  camera.exposure_ms = o.exposure_ms;
  camera.gain = o.gain;
  camera.lock_auto_exposure = o.lock_exposure;
  camera.poll_timeout_ms = o.timeout_ms;
  auto source = std::make_unique<drivers::V4l2Source>(camera);
  const drivers::SourceInfo info = source->info();
  if (guess) {
    in.geometric = calib::pinholeFromFieldOfView(info.width, info.height, o.fov_deg);
    in.geometric_source = "a pinhole guess of " + std::to_string(o.fov_deg) + " degrees (--fov)";
  }
  if (info.width != k.width || info.height != k.height)
    throw InputError(o.calib + ": calibration is for " + std::to_string(k.width) + "x" +
                     std::to_string(k.height) + " images but " + o.live + " delivers " +
                     std::to_string(info.width) + "x" + std::to_string(info.height));
  if (!o.pcalib.empty() || !o.vignette.empty()) {
    in.photometric = calib::loadPhotometricCalibration(o.pcalib, o.vignette, k.width, k.height);
    in.photometric_source = o.pcalib + (o.vignette.empty() ? "" : " " + o.vignette);
  }
  in.name = o.live;
  in.source = std::move(source);
  return in;
#else
  throw DeviceError("run --live: this ldsm was built without the V4L2 source (Linux only)");
#endif
}

const StageTiming* findStage(const std::vector<StageTiming>& stages, const std::string& name) {
  for (const StageTiming& t : stages)
    if (t.stage == name) return &t;
  return nullptr;
}

/// ", dropped 3 (1.2 %), latency 12.3 / 40.1 ms (mean / p99)" for the live modes.
std::string pipelineProgress(const SystemStats& s) {
  char buf[160];
  const StageTiming* lat = findStage(s.latency, "submit_to_tracked");
  std::snprintf(buf, sizeof(buf), ", dropped %lld (%.1f %%), latency %.1f / %.1f ms (mean / p99)",
                static_cast<long long>(s.dropped_frames),
                s.submitted_frames > 0 ? 100.0 * static_cast<double>(s.dropped_frames) /
                                             static_cast<double>(s.submitted_frames)
                                       : 0.0,
                lat ? lat->mean_ms : 0.0, lat ? lat->p99_ms : 0.0);
  return buf;
}

int run(const RunOptions& o) {
  const bool live_input = !o.live.empty() || o.realtime;
  if (o.live.empty() == o.dataset.empty())
    throw ConfigError("run: give either --dataset PATH or --live DEVICE");
  if (live_input && o.deterministic)
    throw ConfigError(
        "run: --deterministic cannot be combined with --realtime or --live (the live pipeline "
        "runs tracking and mapping on their own threads and drops frames when behind)");
  RunInput in = o.live.empty() ? openDatasetInput(o) : openLiveInput(o);
  Config config = o.config.empty() ? Config{} : drivers::loadConfigYaml(o.config);
  if (o.deterministic) config.system.deterministic = true;
  if (o.no_loop) config.loop.enabled = false;
  if (o.no_reuse) config.reuse.enabled = false;
  if (live_input) {
    config.system.deterministic = false;
    config.system.live = true;
  }
  if (o.localize_only) config.map.localize_only = true;
  if (o.fov_deg != 0.0) {
    // Nothing is known of the camera: every part of the calibration has to be found online.
    config.calibration.refine_focal = true;
    config.calibration.refine_principal_point = true;
    const CameraIntrinsics& k = in.geometric.input;
    spdlog::warn(
        "no calibration: self-calibrating from a pinhole guess (horizontal field of view {} "
        "degrees: fx = fy = {:.1f}, cx {:.1f}, cy {:.1f}, no distortion); focal length, principal "
        "point and radial distortion are refined online and the result is written to {}/"
        "camera.txt. Expect a less accurate start than with a calibration.",
        o.fov_deg, k.fx, k.cx, k.cy, o.out);
  }
  std::unique_ptr<System> owned =
      o.load_map.empty() ? std::make_unique<System>(config, in.geometric, in.photometric)
                         : std::make_unique<System>(config, in.geometric, in.photometric,
                                                    drivers::readMapFile(o.load_map), o.load_map);
  System& system = *owned;
  if (!o.load_map.empty())
    std::fprintf(stderr, "%s: map loaded%s; looking for the camera in it\n", o.load_map.c_str(),
                 o.localize_only ? " (localising only: it is not changed)" : "");
  ProgressListener listener;
  // The viewer exists only with --serve: without it nothing of it is in the process.
  std::unique_ptr<viewer::RunViewer> view;
  if (!o.serve.empty()) {
    const std::string mode = live_input                    ? "live"
                             : config.system.deterministic ? "deterministic"
                                                           : "offline";
    view = std::make_unique<viewer::RunViewer>(system, o.serve, o.web_root, in.name, mode);
    std::fprintf(stderr, "viewer: %s\n", view->url().c_str());
  }
  system.setListener(view ? view->listener(&listener) : &listener);
  spdlog::info("{}: {} frames, calibration {}, photometric {}", in.name,
               in.frame_count >= 0 ? std::to_string(in.frame_count) : "live", in.geometric_source,
               in.photometric_source);
  const InterruptHandler interrupt;
  if (o.realtime)
    std::fprintf(stderr, "%s: real-time replay at %gx (Ctrl-C stops and keeps the results)\n",
                 in.name.c_str(), o.speed);
  else if (live_input)
    std::fprintf(stderr, "%s: live camera (Ctrl-C stops and keeps the results)\n", in.name.c_str());

  const bool tty = isatty(fileno(stderr)) != 0;
  const std::int64_t total = in.frame_count < 0 ? o.max_frames
                             : o.max_frames > 0
                                 ? std::min<std::int64_t>(o.max_frames, in.frame_count)
                                 : in.frame_count;
  const auto start = std::chrono::steady_clock::now();
  auto last_print = start;
  auto last_flush = start;
  std::string status = "finished";
  // With a bounded frame history (system.frame_history; live input by default) the poses that
  // leave memory are kept on disk beside the outputs until the whole trajectory is written.
  drivers::TrajectorySpill spill(
      (std::filesystem::path(o.out) / ".trajectory-retired.bin").string());
  const auto keepRetired = [&] {
    try {
      spill.append(system.takeRetiredFrames());
    } catch (const Error& e) {
      spdlog::warn("{}", e.what());  // kept and tried again with the next ones
    }
  };
  bool spill_read = true;
  const auto wholeTrajectory = [&] {
    try {
      return spill.read(system.trajectory());
    } catch (const Error& e) {
      spill_read = false;
      spdlog::error("{} (the trajectory written holds the frames in memory only)", e.what());
      return system.trajectory();
    }
  };
  drivers::Frame frame;
  std::int64_t n = 0;
  try {
    while ((o.max_frames <= 0 || n < o.max_frames) && in.source->next(frame)) {
      if (InterruptHandler::requested()) {
        status = "stopped: interrupted";
        break;
      }
      system.submit({frame.image.view(), frame.timestamp, frame.exposure_ms});
      ++n;
      if (n % 256 == 0) keepRetired();
      const auto now = std::chrono::steady_clock::now();
      if (o.flush_every_s > 0.0 &&
          std::chrono::duration<double>(now - last_flush).count() >= o.flush_every_s) {
        // Published snapshots: tracking does not wait. A failed flush (full disk) is reported
        // and the run goes on; the previous files stay whole.
        try {
          keepRetired();
          writeTrajectoriesSoFar(o.out, system, wholeTrajectory());
        } catch (const Error& e) {
          spdlog::warn("periodic flush: {}", e.what());
        }
        last_flush = now;
      }
      const double since = std::chrono::duration<double>(now - last_print).count();
      const bool milestone = total > 0 ? (n * 10 / total) != ((n - 1) * 10 / total) : since >= 5.0;
      // stats() and trajectory() read published counters, snapshots and the lock-free frame log:
      // they never make tracking wait (calling both on every frame of a 30 Hz live replay left
      // the tracking latency as it was). The rate below is only what a reader can follow.
      constexpr double kRefreshS = 0.25;
      if ((tty && since > kRefreshS) || (!tty && milestone) || n == total) {
        const double el = std::chrono::duration<double, std::milli>(now - start).count();
        const std::string extra = live_input ? pipelineProgress(system.stats()) : std::string();
        std::fprintf(stderr, "%s[%lld/%s] %.1f ms/frame, %d keyframes, %s%s%s", tty ? "\r" : "",
                     static_cast<long long>(n), total > 0 ? std::to_string(total).c_str() : "live",
                     el / n, listener.keyframes.load(), toString(system.status()), extra.c_str(),
                     tty ? "   " : "\n");
        last_print = now;
      }
    }
    if (InterruptHandler::requested() && status == "finished") status = "stopped: interrupted";
  } catch (const Error& e) {
    status = std::string("stopped: ") + e.what();
    spdlog::error("{}", e.what());
  }
  if (tty) std::fputc('\n', stderr);
  system.finish();
  if (view) view->finish();
  RunSummary summary;
  summary.dataset = in.name;
  summary.calibration = in.geometric;
  summary.calibration_source = in.geometric_source;
  summary.status = status;
  summary.mode = live_input ? "live" : config.system.deterministic ? "deterministic" : "offline";
  if (in.replay) {
    summary.realtime_speed = in.replay->speed();
    summary.max_source_lateness_ms = in.replay->maxLatenessMs();
  }
  summary.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const SystemStats stats = system.stats();
  if (const StageTiming* t = findStage(stats.stages, "total")) summary.ms_per_frame = t->mean_ms;
  summary.peak_rss_mb = peakRssMb();
  keepRetired();
  const Trajectory traj = wholeTrajectory();
  if (!o.no_eval && in.dataset) summary.ate = evaluate(*in.dataset, traj);
  bool written = true;
  try {
    writeRunOutputs(o.out, system, traj, summary);
    if (spill_read) spill.remove();  // trajectory.txt holds its poses now
  } catch (const Error& e) {
    // The run's figures below still matter; the files that could be written were.
    std::fprintf(stderr, "ldsm: error: %s\n", e.what());
    written = false;
  }
  if (!o.save_map.empty()) {
    // Also after Ctrl-C or a bad frame: the map so far is what there is.
    try {
      const std::vector<std::uint8_t> map = system.saveMap();
      drivers::writeMapFile(o.save_map, map);
      std::printf("map saved to %s (%.1f MB)\n", o.save_map.c_str(),
                  static_cast<double>(map.size()) / 1e6);
    } catch (const Error& e) {
      std::fprintf(stderr, "ldsm: error: saving the map: %s\n", e.what());
      written = false;
    }
  }

  std::printf("%s: %lld frames, %lld tracked, %lld keyframes, %.1f ms/frame, peak %.0f MB\n",
              status.c_str(), static_cast<long long>(stats.frames),
              static_cast<long long>(stats.tracked_frames), static_cast<long long>(stats.keyframes),
              summary.ms_per_frame, summary.peak_rss_mb);
  if (live_input) {
    const StageTiming* lat = findStage(stats.latency, "submit_to_tracked");
    const StageTiming* all = findStage(stats.latency, "submit_to_processed");
    std::printf(
        "pipeline: %lld submitted, %lld dropped, queue depth max %d of %d (mean %.2f), latency "
        "submit->tracked mean %.1f p50 %.1f p99 %.1f ms (every frame, the initialisation "
        "included: p99 %.1f, max %.1f ms)\n",
        static_cast<long long>(stats.submitted_frames),
        static_cast<long long>(stats.dropped_frames), stats.max_queue_depth, stats.queue_capacity,
        stats.mean_queue_depth, lat ? lat->mean_ms : 0.0, lat ? lat->p50_ms : 0.0,
        lat ? lat->p99_ms : 0.0, all ? all->p99_ms : 0.0, all ? all->max_ms : 0.0);
  }
  if (summary.ate)
    std::printf("ATE %.4f m (%.2f %% of %.2f m path) over %zu poses\n", summary.ate->rmse,
                100.0 * summary.ate->rmse / std::max(summary.ate->gt_path_length, 1e-9),
                summary.ate->gt_path_length, summary.ate->matched);
  if (written)
    std::printf(
        "outputs in %s (trajectory.txt, keyframes.txt, points.ply, stats.json, camera.txt)\n",
        o.out.c_str());
  else
    std::printf("outputs in %s incomplete: see the error above\n", o.out.c_str());
  if (view && o.serve_wait && !InterruptHandler::requested()) {
    std::fprintf(stderr, "viewer: %s still serving the final map; Ctrl-C stops\n",
                 view->url().c_str());
    while (!InterruptHandler::requested())
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  // A camera runs until Ctrl-C: that is its normal end.
  const bool ok = status == "finished" || (!o.live.empty() && status == "stopped: interrupted");
  return ok && written ? 0 : 1;
}

}  // namespace

void addRunCommand(CLI::App& app, CommandResult& result) {
  auto* cmd = app.add_subcommand("run", "Run SLAM on a recorded sequence or a live camera");
  auto o = std::make_shared<RunOptions>();
  auto* dataset = cmd->add_option("--dataset", o->dataset, "Sequence folder or video file");
  auto* live = cmd->add_option("--live", o->live,
                               "Run on a V4L2 camera, e.g. /dev/video0 "
                               "(needs --calib)");
  dataset->excludes(live);
  cmd->add_option("--format", o->format, "auto, tum-mono, euroc, kitti, tum-rgbd, folder, video")
      ->capture_default_str();
  cmd->add_option("--calib", o->calib, "Calibration file (default: the dataset's own)");
  cmd->add_option("--fov", o->fov_deg,
                  "No calibration: start from a pinhole of this horizontal field of view "
                  "(degrees, 20-160) and refine focal length, principal point and distortion "
                  "online; the result is written to the output folder's camera.txt");
  cmd->add_option("--config", o->config, "Configuration YAML (see ldsm config --print-defaults)");
  cmd->add_option("--out", o->out, "Output folder")->capture_default_str();
  cmd->add_flag("--deterministic", o->deterministic, "One thread, bit-identical results");
  cmd->add_flag("--no-loop", o->no_loop, "Turn loop closure off");
  cmd->add_flag("--no-reuse", o->no_reuse,
                "Turn map reuse off (no map keyframes back in the window)");
  cmd->add_option("--max-frames", o->max_frames, "Stop after N frames");
  cmd->add_flag("--no-eval", o->no_eval, "Do not evaluate against the dataset's ground truth");
  cmd->add_option("--flush-every", o->flush_every_s,
                  "Rewrite trajectory.txt and keyframes.txt every SEC seconds during the run, so "
                  "a crash or power cut loses at most that much (0: only at the end)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 86400.0));
  auto* realtime = cmd->add_flag("--realtime", o->realtime,
                                 "Replay the dataset at its own timestamps through the live "
                                 "pipeline (frames dropped when tracking falls behind)");
  realtime->needs(dataset);
  cmd->add_option("--speed", o->speed, "Replay speed with --realtime (1: recorded rate)")
      ->needs(realtime)
      ->check(CLI::Range(0.001, 1000.0))
      ->capture_default_str();
  const char* cam = "Live camera";
  cmd->add_option("--pcalib", o->pcalib, "Inverse response file (pcalib.txt) with --live")
      ->group(cam);
  cmd->add_option("--vignette", o->vignette, "Vignette image with --live")->group(cam);
  cmd->add_option("--width", o->width, "Camera width (default: the calibration's)")->group(cam);
  cmd->add_option("--height", o->height, "Camera height (default: the calibration's)")->group(cam);
  cmd->add_option("--fps", o->fps, "Camera frame rate (default: the device's)")->group(cam);
  cmd->add_option("--pixel-format", o->pixel_formats,
                  "Pixel formats in order of preference: GREY, Y10, Y16, YUYV, MJPEG")
      ->group(cam);
  cmd->add_option("--exposure-ms", o->exposure_ms, "Manual exposure time (auto exposure off)")
      ->group(cam);
  cmd->add_option("--gain", o->gain, "Manual gain in the device's units")->group(cam);
  cmd->add_flag("--lock-exposure", o->lock_exposure, "Freeze the auto exposure at start")
      ->group(cam);
  cmd->add_option("--timeout-ms", o->timeout_ms, "Longest wait for a camera frame")
      ->capture_default_str()
      ->group(cam);
  const char* maps = "Maps across sessions (docs/map-file.md)";
  cmd->add_option("--load-map", o->load_map,
                  "Start in a saved map: relocalise in it, continue in its frame")
      ->group(maps);
  cmd->add_option("--save-map", o->save_map,
                  "Save the map at the end of the run (also after Ctrl-C)")
      ->group(maps);
  cmd->add_flag("--localize-only", o->localize_only,
                "With --load-map: localise in the map without changing it (flat memory)")
      ->needs("--load-map")
      ->group(maps);
  const char* viewer = "Browser viewer (docs/viewer.md)";
  auto* serve = cmd->add_option("--serve", o->serve,
                                "Serve a live 3D view of the run at [ADDR:]PORT (default address "
                                "127.0.0.1), e.g. --serve 8080")
                    ->group(viewer);
  cmd->add_flag("--serve-wait", o->serve_wait,
                "After the run, keep serving the final map until Ctrl-C")
      ->needs(serve)
      ->group(viewer);
  cmd->add_option("--web-root", o->web_root,
                  "The viewer's page folder (default: share/ldsm/web beside the executable)")
      ->needs(serve)
      ->group(viewer);
  cmd->callback([o, &result]() { result.exit_code = run(*o); });
}

}  // namespace ldsm::app
