// What loop closure costs the tracking, and what it buys: each sequence is replayed in real time
// (RealtimeReplaySource at its recorded rate) through the live, threaded pipeline, once with loop
// closure and once without (--no-loop), each run in its own process. Prints per run: frames
// received and dropped, loops closed, ATE, tracking latency from submit() to the published pose
// (p50 / p99), the tracking stage's own p99, and peak RSS; then the p99 ratio (target: loop
// closure raises the tracking latency p99 by less than 10 %).
//
//   bench_loop_latency [--data DIR] [--only NAME[,NAME...]] [--speed X]
//
// sim:loop-f2 is the synthetic corridor loop with the focal length told 2 % off (so that the
// odometry drifts and the loop has something to correct).
#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "bench_input.h"
#include "ldsm/drivers/realtime_replay_source.h"
#include "ldsm/eval/ate.h"
#include "run_in_child.h"

namespace {

using ldsm::bench::cell;

struct Sequence {
  std::string name;
  std::string folder;  ///< below --data; empty for a synthetic scene
  std::string scene;
  double focal_error = 0.0;
};

struct Result {
  long long received = 0, dropped = 0, loops = 0;
  double ate = NAN;
  double latency_p50 = NAN, latency_p99 = NAN, track_p99 = NAN;
  char error[200] = {};
};

const ldsm::StageTiming* find(const std::vector<ldsm::StageTiming>& v, const char* name) {
  for (const auto& t : v)
    if (t.stage == name) return &t;
  return nullptr;
}

Result runOnce(const Sequence& s, const std::string& data, bool loop, double speed) {
  ldsm::Config config;
  config.system.deterministic = false;
  config.system.live = true;
  config.loop.enabled = loop;
  ldsm::bench::BenchInput in =
      ldsm::bench::openBenchInput(config, data + "/" + s.folder, s.scene, 0, s.focal_error);
  std::unique_ptr<ldsm::System>& system = in.system;
  const ldsm::Trajectory& gt = in.ground_truth;
  ldsm::drivers::RealtimeReplaySource source(std::move(in.source), speed);
  ldsm::drivers::Frame f;
  while (source.next(f)) system->submit({f.image.view(), f.timestamp, f.exposure_ms});
  system->finish();
  const ldsm::SystemStats st = system->stats();
  Result r;
  r.received = st.frames;
  r.dropped = st.dropped_frames;
  r.loops = static_cast<long long>(st.loops_closed);
  if (const auto* t = find(st.latency, "submit_to_tracked")) {
    r.latency_p50 = t->p50_ms;
    r.latency_p99 = t->p99_ms;
  }
  if (const auto* t = find(st.stages, "track")) r.track_p99 = t->p99_ms;
  const ldsm::Trajectory est = system->trajectory();
  if (!gt.empty() && est.size() >= 3) r.ate = ldsm::eval::computeAte(gt, est).rmse;
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  spdlog::set_level(spdlog::level::warn);
  std::string data = LDSM_BENCH_DATA;
  std::string only;
  double speed = 1.0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (ldsm::bench::takeSequenceOption(argc, argv, i, data, only)) {
      continue;
    } else if (a == "--speed" && i + 1 < argc) {
      speed = std::stod(argv[++i]);
    } else {
      std::fprintf(stderr, "usage: %s [--data DIR] [--only NAME,...] [--speed X]\n", argv[0]);
      return 2;
    }
  }
  const std::vector<Sequence> all = {
      {"vamr_desk_loop", "vamr_desk_loop", "", 0.0},
      {"sim:loop-f2", "", "loop", 0.02},
  };
  std::printf("%-16s %-5s %8s %7s %5s %9s %8s %8s %9s %7s\n", "sequence", "loop", "received",
              "dropped", "loops", "ATE [m]", "lat p50", "lat p99", "track p99", "RSS MB");
  for (const Sequence& s : all) {
    if (!ldsm::bench::selected(only, s.name)) continue;
    if (!s.folder.empty() && !std::filesystem::is_directory(data + "/" + s.folder)) {
      std::printf("%-16s skipped: %s/%s not found\n", s.name.c_str(), data.c_str(),
                  s.folder.c_str());
      continue;
    }
    double p99[2] = {NAN, NAN};
    for (int loop = 0; loop < 2; ++loop) {
      Result r;
      double rss = 0.0;
      const auto status = ldsm::bench::runInChild(
          [&](Result& out) { out = runOnce(s, data, loop == 1, speed); }, r, rss);
      if (status != ldsm::bench::ChildStatus::kOk) {
        std::printf("%-16s %-5s %s\n", s.name.c_str(), loop ? "on" : "off",
                    status == ldsm::bench::ChildStatus::kError ? r.error : "crashed");
        continue;
      }
      p99[loop] = r.latency_p99;
      std::printf("%-16s %-5s %8lld %7lld %5lld %9s %8s %8s %9s %7.0f\n", s.name.c_str(),
                  loop ? "on" : "off", r.received, r.dropped, r.loops, cell(r.ate, "%.4f").c_str(),
                  cell(r.latency_p50, "%.1f").c_str(), cell(r.latency_p99, "%.1f").c_str(),
                  cell(r.track_p99, "%.1f").c_str(), rss);
    }
    const double rise = 100.0 * (p99[1] / p99[0] - 1.0);
    std::printf("%-16s latency p99 with loop closure: %s %% (target < +10 %%)\n", s.name.c_str(),
                cell(rise, "%+.1f").c_str());
  }
  return 0;
}
