// Runs the odometry on the real sequences of ../shared/data and on synthetic scenes, each in its
// own process (so that peak memory is per sequence), and prints one table: frames, ATE after
// Sim(3) alignment, time per frame (mean and p99 of the whole per-frame processing), peak RSS,
// and the targets of the odometry issue.
//
//   bench_sequences [--data DIR] [--only NAME[,NAME...]] [--check]
//
// Deterministic mode, one thread. --check exits non-zero when a target is missed.
#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "bench_input.h"
#include "ldsm/drivers/machine_info.h"
#include "ldsm/error.h"
#include "ldsm/eval/ate.h"
#include "ldsm/system.h"
#include "run_in_child.h"

namespace {

using ldsm::bench::cell;

struct Target {
  double ate_m = NAN;
  double ms_per_frame = NAN;
  double rss_mb = NAN;
};

struct Sequence {
  std::string name;
  std::string folder;  ///< below --data; empty for synthetic scenes
  std::string scene;   ///< synthetic scene name
  std::int64_t frames = 0;
  Target target;
};

struct Result {
  long long frames = 0, tracked = 0, keyframes = 0;
  double ate = NAN, path = NAN, ms_mean = NAN, ms_p99 = NAN;
  char error[200] = {};
};

Result runSequence(const Sequence& s, const std::string& data) {
  Result r;
  ldsm::Config config;
  config.system.deterministic = true;
  // The odometry targets (issue 3) are measured without loop closure; loops have their own bench.
  config.loop.enabled = false;
  ldsm::bench::BenchInput in =
      ldsm::bench::openBenchInput(config, data + "/" + s.folder, s.scene, s.frames);
  std::unique_ptr<ldsm::drivers::FrameSource>& source = in.source;
  std::unique_ptr<ldsm::System>& system = in.system;
  const ldsm::Trajectory& gt = in.ground_truth;
  ldsm::drivers::Frame f;
  while (source->next(f)) system->submit({f.image.view(), f.timestamp, f.exposure_ms});
  system->finish();
  const ldsm::SystemStats st = system->stats();
  r.frames = st.frames;
  r.tracked = st.tracked_frames;
  r.keyframes = st.keyframes;
  for (const auto& t : st.stages)
    if (t.stage == "total") {
      r.ms_mean = t.mean_ms;
      r.ms_p99 = t.p99_ms;
    }
  const ldsm::Trajectory est = system->trajectory();
  if (!gt.empty() && est.size() >= 3) {
    const auto ate = ldsm::eval::computeAte(gt, est);
    r.ate = ate.rmse;
    r.path = ate.gt_path_length;
  }
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  spdlog::set_level(spdlog::level::warn);
  std::string data = LDSM_BENCH_DATA;
  std::string only;
  bool check = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--data" && i + 1 < argc)
      data = argv[++i];
    else if (a == "--only" && i + 1 < argc)
      only = argv[++i];
    else if (a == "--check")
      check = true;
    else {
      std::fprintf(stderr, "usage: %s [--data DIR] [--only NAME,...] [--check]\n", argv[0]);
      return 2;
    }
  }
  // Timings and even accuracy figures depend on the machine (docs/determinism.md): say which.
  std::printf("machine: %s\n",
              ldsm::drivers::machineSummary(ldsm::drivers::describeMachine()).c_str());
  const std::vector<Sequence> all = {
      {"kitti00_200", "kitti00_200", "", 0, {0.90, 75.0, 150.0}},
      {"vamr_desk_loop", "vamr_desk_loop", "", 0, {0.0010, 25.0, 150.0}},
      {"euroc_v101_static95", "euroc_v101_static95", "", 0, {}},
      {"sim:forward", "", "forward", 600, {}},
      {"sim:rotation", "", "rotation", 600, {}},
      {"sim:loop", "", "loop", 0, {}},
  };
  std::printf("%-20s %6s %6s %5s %10s %7s %8s %8s %8s  %s\n", "sequence", "frames", "track", "KFs",
              "ATE [m]", "ATE %", "ms/frame", "p99 ms", "RSS MB", "targets");
  bool all_ok = true;
  for (const Sequence& s : all) {
    if (!only.empty() && ("," + only + ",").find("," + s.name + ",") == std::string::npos) continue;
    if (!s.folder.empty() && !std::filesystem::is_directory(data + "/" + s.folder)) {
      std::printf("%-20s skipped: %s/%s not found\n", s.name.c_str(), data.c_str(),
                  s.folder.c_str());
      continue;
    }
    Result r;
    double rss = 0.0;
    const ldsm::bench::ChildStatus status =
        ldsm::bench::runInChild([&](Result& out) { out = runSequence(s, data); }, r, rss);
    if (status == ldsm::bench::ChildStatus::kCrashed) {
      std::printf("%-20s crashed\n", s.name.c_str());
      all_ok = false;
      continue;
    }
    if (status == ldsm::bench::ChildStatus::kError) {
      std::printf("%-20s error: %s\n", s.name.c_str(), r.error);
      all_ok = false;
      continue;
    }
    std::string verdict;
    auto judge = [&](const char* what, double value, double limit) {
      if (std::isnan(limit)) return;
      const bool ok = !std::isnan(value) && value <= limit;
      all_ok = all_ok && ok;
      verdict += std::string(what) + (ok ? " ok " : " MISS ");
    };
    judge("ATE", r.ate, s.target.ate_m);
    judge("ms", r.ms_mean, s.target.ms_per_frame);
    judge("RSS", rss, s.target.rss_mb);
    std::printf("%-20s %6lld %6lld %5lld %10s %7s %8s %8s %8.0f  %s\n", s.name.c_str(), r.frames,
                r.tracked, r.keyframes, cell(r.ate, "%.4f").c_str(),
                cell(100.0 * r.ate / r.path, "%.2f").c_str(), cell(r.ms_mean, "%.1f").c_str(),
                cell(r.ms_p99, "%.1f").c_str(), rss, verdict.c_str());
    std::fflush(stdout);
  }
  return check && !all_ok ? 1 : 0;
}
