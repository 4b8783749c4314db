// `ldsm eval`: compare an estimated trajectory with ground truth. Prints a one-line summary (ATE,
// KITTI-style RPE, TUM-mono loop drift) and optionally writes a JSON report and a top-view plot.
#include <spdlog/spdlog.h>

#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.h"
#include "ldsm/drivers/atomic_file.h"
#include "ldsm/drivers/json_writer.h"
#include "ldsm/drivers/trajectory_io.h"
#include "ldsm/error.h"
#include "ldsm/eval/ate.h"
#include "ldsm/eval/loop_drift.h"
#include "ldsm/eval/rpe.h"
#include "plot_trajectory.h"

namespace ldsm::app {

namespace {

struct EvalOptions {
  std::string gt_path;
  std::string est_path;
  std::string align = "sim3";
  double max_dt = 0.02;
  std::string gt_format = "auto";
  std::string est_format = "auto";
  std::string gt_times;
  std::string est_times;
  std::vector<double> rpe_lengths;
  std::size_t rpe_step = 1;
  std::size_t segment = 0;
  std::string plot_path;
  std::string json_path;
  /// Another estimate in the same frame (e.g. the session that saved a map): the ATE is also
  /// measured under the alignment of that one.
  std::string align_as_path;
  std::string align_as_format = "auto";
  std::string align_as_times;
};

struct LoadedTrajectory {
  std::string path;
  drivers::TrajectoryFormat format = drivers::TrajectoryFormat::Auto;
  Trajectory poses;
};

LoadedTrajectory load(const std::string& path, const std::string& format_name,
                      const std::string& times_path, const char* times_option) {
  LoadedTrajectory t;
  t.path = path;
  t.format = drivers::parseTrajectoryFormat(format_name);
  if (t.format == drivers::TrajectoryFormat::Auto) t.format = drivers::detectTrajectoryFormat(path);
  std::optional<std::vector<double>> times;
  if (!times_path.empty()) {
    if (t.format != drivers::TrajectoryFormat::Kitti) {
      throw ConfigError(std::string(times_option) + " applies to KITTI pose files only, but " +
                        path + " is " + drivers::trajectoryFormatName(t.format));
    }
    times = drivers::readTimestampList(times_path);
  }
  t.poses = drivers::readTrajectory(path, t.format, times ? &*times : nullptr);
  return t;
}

struct EvalResults {
  eval::AteResult ate;
  /// With --align-as: the estimate under the reference's alignment, and the reference's own ATE.
  std::optional<eval::AteResult> ate_under_reference;
  std::optional<eval::AteResult> reference_ate;
  eval::RpeResult rpe;
  double rpe_scale = 1.0;
  std::optional<eval::LoopDriftResult> drift;
  std::string drift_error;
};

std::string summaryLine(const EvalResults& r) {
  char buf[512];
  const double percent =
      r.ate.gt_path_length > 0.0 ? 100.0 * r.ate.rmse / r.ate.gt_path_length : 0.0;
  std::snprintf(buf, sizeof(buf), "ATE rmse %.4g m (%.3g %% of %.4g m path) over %zu poses",
                r.ate.rmse, percent, r.ate.gt_path_length, r.ate.matched);
  std::string line = buf;
  if (r.rpe.valid()) {
    std::snprintf(buf, sizeof(buf), ", RPE %.4g %% %.4g deg/m over %zu segments",
                  r.rpe.translation_percent, r.rpe.rotation_deg_per_m, r.rpe.segments);
  } else {
    std::snprintf(buf, sizeof(buf), ", RPE n/a (path too short for the segment lengths)");
  }
  line += buf;
  if (r.drift) {
    std::snprintf(buf, sizeof(buf), ", e_align %.4g m (e_t %.4g m, e_r %.4g deg, e_s %.4g)",
                  r.drift->alignment_error, r.drift->translation_drift, r.drift->rotation_drift_deg,
                  r.drift->scale_drift);
  } else {
    std::snprintf(buf, sizeof(buf), ", e_align n/a");
  }
  line += buf;
  if (r.ate_under_reference) {
    std::snprintf(
        buf, sizeof(buf),
        "\nATE rmse %.4g m over %zu poses under the alignment of the reference (which has "
        "%.4g m under its own)",
        r.ate_under_reference->rmse, r.ate_under_reference->matched, r.reference_ate->rmse);
    line += buf;
  }
  return line;
}

void writeAlignment(drivers::JsonWriter& w, const eval::Alignment& a) {
  w.beginObject();
  w.key("scale").value(a.scale);
  w.key("rotation")
      .array({a.rotation(0, 0), a.rotation(0, 1), a.rotation(0, 2), a.rotation(1, 0),
              a.rotation(1, 1), a.rotation(1, 2), a.rotation(2, 0), a.rotation(2, 1),
              a.rotation(2, 2)});
  w.key("translation").array({a.translation.x(), a.translation.y(), a.translation.z()});
  w.endObject();
}

void writeInput(drivers::JsonWriter& w, const LoadedTrajectory& t) {
  w.beginObject();
  w.key("path").value(t.path);
  w.key("format").value(drivers::trajectoryFormatName(t.format));
  w.key("poses").value(static_cast<std::uint64_t>(t.poses.size()));
  w.endObject();
}

std::string jsonReport(const EvalOptions& o, const LoadedTrajectory& gt,
                       const LoadedTrajectory& est, const EvalResults& r) {
  drivers::JsonWriter w;
  w.beginObject();
  w.key("gt");
  writeInput(w, gt);
  w.key("est");
  writeInput(w, est);
  w.key("align").value(o.align);
  w.key("max_dt").value(o.max_dt);

  w.key("ate").beginObject();
  w.key("rmse").value(r.ate.rmse);
  w.key("mean").value(r.ate.mean);
  w.key("median").value(r.ate.median);
  w.key("max").value(r.ate.max);
  w.key("rotation_rmse_deg").value(r.ate.rotation_rmse_deg);
  w.key("matched").value(static_cast<std::uint64_t>(r.ate.matched));
  w.key("gt_path_length").value(r.ate.gt_path_length);
  w.key("percent_of_path")
      .value(r.ate.gt_path_length > 0.0 ? 100.0 * r.ate.rmse / r.ate.gt_path_length : 0.0);
  w.key("sim3_scale").value(r.ate.sim3_scale);
  w.key("alignment");
  writeAlignment(w, r.ate.alignment);
  w.endObject();

  if (r.ate_under_reference) {
    w.key("align_as").beginObject();
    w.key("path").value(o.align_as_path);
    w.key("reference_rmse").value(r.reference_ate->rmse);
    w.key("reference_matched").value(static_cast<std::uint64_t>(r.reference_ate->matched));
    w.key("rmse").value(r.ate_under_reference->rmse);
    w.key("max").value(r.ate_under_reference->max);
    w.key("matched").value(static_cast<std::uint64_t>(r.ate_under_reference->matched));
    w.key("alignment");
    writeAlignment(w, r.ate_under_reference->alignment);
    w.endObject();
  }

  w.key("rpe");
  if (r.rpe.valid()) {
    w.beginObject();
    w.key("segments").value(static_cast<std::uint64_t>(r.rpe.segments));
    w.key("translation_percent").value(r.rpe.translation_percent);
    w.key("rotation_deg_per_m").value(r.rpe.rotation_deg_per_m);
    w.key("scale_applied").value(r.rpe_scale);
    w.key("step").value(static_cast<std::uint64_t>(o.rpe_step));
    w.key("lengths").beginArray();
    for (const auto& l : r.rpe.per_length) {
      w.beginObject();
      w.key("length").value(l.length);
      w.key("segments").value(static_cast<std::uint64_t>(l.segments));
      w.key("translation_percent").value(l.translation_percent);
      w.key("rotation_deg_per_m").value(l.rotation_deg_per_m);
      w.endObject();
    }
    w.endArray();
    w.endObject();
  } else {
    w.null();
  }

  w.key("loop_drift");
  if (r.drift) {
    const eval::LoopDriftResult& d = *r.drift;
    w.beginObject();
    w.key("start_poses").value(static_cast<std::uint64_t>(d.start_poses));
    w.key("end_poses").value(static_cast<std::uint64_t>(d.end_poses));
    w.key("e_align").value(d.alignment_error);
    w.key("e_align_segments").value(d.alignment_error_segments);
    w.key("e_t").value(d.translation_drift);
    w.key("e_r_deg").value(d.rotation_drift_deg);
    w.key("e_s").value(d.scale_drift);
    w.key("drift");
    writeAlignment(w, d.drift);
    w.endObject();
  } else {
    w.null();
    w.key("loop_drift_error").value(r.drift_error);
  }
  w.endObject();
  return w.str();
}

std::vector<Eigen::Vector3d> positions(const Trajectory& t) {
  std::vector<Eigen::Vector3d> out;
  out.reserve(t.size());
  for (const auto& sp : t) out.push_back(sp.pose.translation);
  return out;
}

void run(const EvalOptions& o) {
  const LoadedTrajectory gt = load(o.gt_path, o.gt_format, o.gt_times, "--gt-times");
  const LoadedTrajectory est = load(o.est_path, o.est_format, o.est_times, "--est-times");
  const eval::AlignMode mode = o.align == "se3" ? eval::AlignMode::SE3 : eval::AlignMode::Sim3;

  // Untimed KITTI poses are stamped 0, 1, 2, ...: matching them against real timestamps would
  // pair arbitrary poses. Two untimed KITTI files match by index, which is what KITTI means.
  const bool gt_untimed = gt.format == drivers::TrajectoryFormat::Kitti && o.gt_times.empty();
  const bool est_untimed = est.format == drivers::TrajectoryFormat::Kitti && o.est_times.empty();
  if (gt_untimed != est_untimed) {
    throw InputError((gt_untimed ? gt.path : est.path) +
                     ": KITTI poses carry no timestamps; pass " +
                     (gt_untimed ? "--gt-times" : "--est-times") +
                     " (or give both trajectories as KITTI files to match them by index)");
  }

  EvalResults r;
  r.ate = eval::computeAte(gt.poses, est.poses, mode, o.max_dt);
  if (2 * r.ate.matched < est.poses.size()) {
    spdlog::warn("only {} of {} estimated poses have a ground-truth pose within {} s",
                 r.ate.matched, est.poses.size(), o.max_dt);
  }

  if (!o.align_as_path.empty()) {
    const LoadedTrajectory ref =
        load(o.align_as_path, o.align_as_format, o.align_as_times, "--align-as-times");
    const bool ref_untimed =
        ref.format == drivers::TrajectoryFormat::Kitti && o.align_as_times.empty();
    if (ref_untimed != gt_untimed) {
      throw InputError((ref_untimed ? ref.path : gt.path) +
                       ": KITTI poses carry no timestamps; pass " +
                       (ref_untimed ? "--align-as-times" : "--gt-times") +
                       " (or give both as KITTI files to match them by index)");
    }
    r.reference_ate = eval::computeAte(gt.poses, ref.poses, mode, o.max_dt);
    r.ate_under_reference =
        eval::computeAteUnder(gt.poses, est.poses, r.reference_ate->alignment, o.max_dt);
  }

  eval::RpeOptions rpe;
  rpe.lengths = o.rpe_lengths;
  rpe.step = o.rpe_step;
  rpe.max_dt = o.max_dt;
  // A monocular estimate has no metric scale: evaluate it at the scale of the Sim(3) alignment.
  rpe.scale = mode == eval::AlignMode::Sim3 ? r.ate.alignment.scale : 1.0;
  r.rpe_scale = rpe.scale;
  r.rpe = eval::computeRpe(gt.poses, est.poses, rpe);

  eval::LoopDriftOptions drift;
  drift.segment_poses = o.segment;
  drift.max_dt = o.max_dt;
  try {
    r.drift = eval::computeLoopDrift(gt.poses, est.poses, drift);
  } catch (const InputError& e) {
    r.drift_error = e.what();  // e.g. a straight segment: report the rest anyway
  }

  std::printf("%s\n", summaryLine(r).c_str());
  if (!r.drift_error.empty()) std::printf("loop drift not computed: %s\n", r.drift_error.c_str());
  if (!o.json_path.empty()) drivers::writeFileAtomically(o.json_path, jsonReport(o, gt, est, r));
  if (!o.plot_path.empty()) {
    char title[160];
    std::snprintf(title, sizeof(title), "ATE rmse %.4g m over %zu poses (%s alignment)", r.ate.rmse,
                  r.ate.matched, o.align.c_str());
    writeTopViewPlot(
        o.plot_path,
        {PlotSeries{"ground truth", positions(gt.poses), {40, 40, 40}},
         PlotSeries{"estimate (aligned)", positions(r.ate.aligned_estimate), {214, 39, 40}}},
        title);
  }
}

}  // namespace

void addEvalCommand(CLI::App& app, CommandResult& result) {
  (void)result;  // failures are reported by throwing ldsm::Error
  auto opts = std::make_shared<EvalOptions>();
  CLI::App* sub = app.add_subcommand(
      "eval", "Compare an estimated trajectory with ground truth: ATE, RPE, loop drift");
  const std::vector<std::string> formats{"auto", "tum", "euroc", "kitti"};
  sub->add_option("--gt", opts->gt_path, "Ground-truth trajectory file")->required();
  sub->add_option("--est", opts->est_path, "Estimated trajectory file")->required();
  sub->add_option("--align", opts->align, "Alignment: sim3 (monocular) or se3")
      ->check(CLI::IsMember({"sim3", "se3"}))
      ->capture_default_str();
  sub->add_option("--max-dt", opts->max_dt, "Timestamp tolerance of the association [s]")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  sub->add_option("--gt-format", opts->gt_format, "auto, tum, euroc or kitti")
      ->check(CLI::IsMember(formats))
      ->capture_default_str();
  sub->add_option("--est-format", opts->est_format, "auto, tum, euroc or kitti")
      ->check(CLI::IsMember(formats))
      ->capture_default_str();
  sub->add_option("--gt-times", opts->gt_times, "Timestamps of a KITTI ground truth (times.txt)");
  sub->add_option("--est-times", opts->est_times, "Timestamps of a KITTI estimate (times.txt)");
  sub->add_option("--rpe-lengths", opts->rpe_lengths,
                  "RPE segment lengths [m] (default: 100..800 m, or 10..80 % of short paths)")
      ->delimiter(',')
      ->check(CLI::PositiveNumber);
  sub->add_option("--rpe-step", opts->rpe_step, "Start an RPE segment at every N-th pose")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  sub->add_option("--segment", opts->segment,
                  "Poses in the start and end segment of the loop drift (0: a fifth of the poses)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  sub->add_option("--align-as", opts->align_as_path,
                  "Also measure the estimate under the alignment of this trajectory (one in the "
                  "same frame, e.g. the run that saved the map a --load-map run started in)");
  sub->add_option("--align-as-format", opts->align_as_format, "auto, tum, euroc or kitti")
      ->check(CLI::IsMember(formats))
      ->capture_default_str();
  sub->add_option("--align-as-times", opts->align_as_times,
                  "Timestamps of a KITTI --align-as trajectory (times.txt)");
  sub->add_option("--plot", opts->plot_path, "Write a top-view plot (.png or .svg)");
  sub->add_option("--json", opts->json_path, "Write the results as JSON");
  sub->callback([opts]() { run(*opts); });
}

}  // namespace ldsm::app
