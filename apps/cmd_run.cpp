// `ldsm run`: SLAM on a recorded sequence, with a progress line, writing the trajectory, the
// keyframes, the map and statistics; evaluates against ground truth when the dataset has one.
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <memory>

#include "commands.h"
#include "ldsm/drivers/config_yaml.h"
#include "ldsm/drivers/dataset_calibration.h"
#include "ldsm/drivers/dataset_description.h"
#include "ldsm/drivers/dataset_source.h"
#include "ldsm/drivers/trajectory_io.h"
#include "ldsm/error.h"
#include "ldsm/eval/ate.h"
#include "ldsm/system.h"
#include "run_outputs.h"

namespace ldsm::app {
namespace {

std::atomic<bool> g_interrupted{false};
void onSignal(int) {
  g_interrupted = true;
}

struct RunOptions {
  std::string dataset;
  std::string format = "auto";
  std::string calib;
  std::string config;
  std::string out = "ldsm_out";
  bool deterministic = false;
  bool no_loop = false;
  std::int64_t max_frames = 0;
  bool no_eval = false;
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

int run(const RunOptions& o) {
  const drivers::DatasetDescription desc =
      drivers::describeDataset(o.dataset, drivers::parseDatasetFormat(o.format));
  const drivers::DatasetCalibration calib = drivers::loadDatasetCalibration(desc, o.calib);
  Config config = o.config.empty() ? Config{} : drivers::loadConfigYaml(o.config);
  if (o.deterministic) config.system.deterministic = true;
  if (o.no_loop) config.loop.enabled = false;
  auto source = drivers::openDataset(desc);
  System system(config, calib.geometric, calib.photometric);
  ProgressListener listener;
  system.setListener(&listener);
  spdlog::info("{}: {} frames, calibration {}, photometric {}", o.dataset, desc.frame_count,
               calib.geometric_source, calib.photometric_source);

  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
  const bool tty = isatty(fileno(stderr)) != 0;
  const std::int64_t total =
      o.max_frames > 0 ? std::min<std::int64_t>(o.max_frames, desc.frame_count) : desc.frame_count;
  const auto start = std::chrono::steady_clock::now();
  auto last_print = start;
  std::string status = "finished";
  drivers::Frame frame;
  std::int64_t n = 0;
  try {
    while ((o.max_frames <= 0 || n < o.max_frames) && source->next(frame)) {
      if (g_interrupted) {
        status = "stopped: interrupted";
        break;
      }
      system.submit({frame.image.view(), frame.timestamp, frame.exposure_ms});
      ++n;
      const auto now = std::chrono::steady_clock::now();
      const double since = std::chrono::duration<double>(now - last_print).count();
      const bool milestone = total > 0 && (n * 10 / total) != ((n - 1) * 10 / total);
      if ((tty && since > 0.25) || (!tty && milestone) || n == total) {
        const double el = std::chrono::duration<double, std::milli>(now - start).count();
        std::fprintf(stderr, "%s[%lld/%lld] %.1f ms/frame, %d keyframes, %s%s", tty ? "\r" : "",
                     static_cast<long long>(n), static_cast<long long>(total), el / n,
                     listener.keyframes.load(), toString(system.status()), tty ? "   " : "\n");
        last_print = now;
      }
    }
  } catch (const Error& e) {
    status = std::string("stopped: ") + e.what();
    spdlog::error("{}", e.what());
  }
  if (tty) std::fputc('\n', stderr);
  system.finish();
  RunSummary summary;
  summary.dataset = o.dataset;
  summary.status = status;
  summary.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const SystemStats stats = system.stats();
  for (const StageTiming& t : stats.stages)
    if (t.stage == "total") summary.ms_per_frame = t.mean_ms;
  summary.peak_rss_mb = peakRssMb();
  const Trajectory traj = system.trajectory();
  if (!o.no_eval) summary.ate = evaluate(desc, traj);
  writeRunOutputs(o.out, system, summary);

  std::printf("%s: %lld frames, %lld tracked, %lld keyframes, %.1f ms/frame, peak %.0f MB\n",
              status.c_str(), static_cast<long long>(stats.frames),
              static_cast<long long>(stats.tracked_frames), static_cast<long long>(stats.keyframes),
              summary.ms_per_frame, summary.peak_rss_mb);
  if (summary.ate)
    std::printf("ATE %.4f m (%.2f %% of %.2f m path) over %zu poses\n", summary.ate->rmse,
                100.0 * summary.ate->rmse / std::max(summary.ate->gt_path_length, 1e-9),
                summary.ate->gt_path_length, summary.ate->matched);
  std::printf("outputs in %s (trajectory.txt, keyframes.txt, points.ply, stats.json)\n",
              o.out.c_str());
  return status == "finished" ? 0 : 1;
}

}  // namespace

void addRunCommand(CLI::App& app, CommandResult& result) {
  auto* cmd = app.add_subcommand("run", "Run SLAM on a recorded sequence");
  auto o = std::make_shared<RunOptions>();
  cmd->add_option("--dataset", o->dataset, "Sequence folder or video file")->required();
  cmd->add_option("--format", o->format, "auto, tum-mono, euroc, kitti, tum-rgbd, folder, video")
      ->capture_default_str();
  cmd->add_option("--calib", o->calib, "Calibration file (default: the dataset's own)");
  cmd->add_option("--config", o->config, "Configuration YAML (see ldsm config --print-defaults)");
  cmd->add_option("--out", o->out, "Output folder")->capture_default_str();
  cmd->add_flag("--deterministic", o->deterministic, "One thread, bit-identical results");
  cmd->add_flag("--no-loop", o->no_loop, "Turn loop closure off");
  cmd->add_option("--max-frames", o->max_frames, "Stop after N frames");
  cmd->add_flag("--no-eval", o->no_eval, "Do not evaluate against the dataset's ground truth");
  cmd->callback([o, &result]() { result.exit_code = run(*o); });
}

}  // namespace ldsm::app
