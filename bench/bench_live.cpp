// The live pipeline on the real sequences, replayed at their own timestamps (and faster: a
// machine that many times slower) as `ldsm run --realtime --speed S` does, each run in its own
// process: frames dropped, frames tracked, the pose latency (submit -> tracked: p50, p99, max),
// how many frames the initializer took and went without, and the ATE. One row per round, then
// the median of the rounds per sequence and speed.
//
//   bench_live [--data DIR] [--only NAME[,NAME...]] [--speeds S[,S...]] [--rounds N] [--check]
//
// Live mode, threaded (tracking, mapping and the initializer on threads of their own), default
// configuration. Timing moves from round to round on shared machines: take several rounds on an
// otherwise idle machine. --check exits non-zero when issue 19's live target is missed at 1x
// (median p99 <= 15 ms and no frame dropped in any round).
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "bench_input.h"
#include "ldsm/drivers/allocator_policy.h"
#include "ldsm/drivers/machine_info.h"
#include "ldsm/drivers/realtime_replay_source.h"
#include "ldsm/eval/ate.h"
#include "ldsm/system.h"
#include "run_in_child.h"

namespace {

using ldsm::bench::cell;

/// Issue 19's live target at the recorded rate.
constexpr double kTargetP99Ms = 15.0;

struct Result {
  long long submitted = 0, dropped = 0, tracked = 0, losses = 0, maps = 0;
  long long init_frames = 0, init_busy = 0;
  double p50_ms = NAN, p99_ms = NAN, max_ms = NAN, ate = NAN;
  char error[200] = {};
};

Result runLive(const std::string& folder, double speed) {
  ldsm::Config config;
  config.system.live = true;
  ldsm::bench::BenchInput in = ldsm::bench::openBenchInput(config, folder, "");
  ldsm::drivers::RealtimeReplaySource source(std::move(in.source), speed);
  Result r;
  ldsm::drivers::Frame f;
  while (source.next(f)) in.system->submit({f.image.view(), f.timestamp, f.exposure_ms});
  in.system->finish();
  const ldsm::SystemStats s = in.system->stats();
  r.submitted = s.submitted_frames;
  r.dropped = s.dropped_frames;
  r.tracked = s.tracked_frames;
  r.losses = s.tracking_losses;
  r.maps = s.initializations;
  r.init_frames = s.initializer_frames;
  r.init_busy = s.initializer_busy_frames;
  for (const ldsm::StageTiming& t : s.latency)
    if (t.stage == "submit_to_tracked" && t.count > 0) {
      r.p50_ms = t.p50_ms;
      r.p99_ms = t.p99_ms;
      r.max_ms = t.max_ms;
    }
  const ldsm::Trajectory est = in.system->trajectory();
  if (!in.ground_truth.empty() && est.size() >= 3)
    r.ate = ldsm::eval::computeAte(in.ground_truth, est).rmse;
  return r;
}

double median(std::vector<double> v) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return std::isnan(x); }), v.end());
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// "1,2,4" -> {1, 2, 4}; empty when a value is not a speed RealtimeReplaySource takes.
std::vector<double> parseSpeeds(const std::string& list) {
  std::vector<double> speeds;
  std::stringstream in(list);
  for (std::string item; std::getline(in, item, ',');) {
    char* end = nullptr;
    const double s = std::strtod(item.c_str(), &end);
    if (item.empty() || *end != '\0' || !(s > 0.0) || s > 1000.0) return {};
    speeds.push_back(s);
  }
  return speeds;
}

void printRow(const std::string& label, const Result& r) {
  std::printf("%-28s %6lld %6lld %6lld %4lld/%-3lld %5lld/%-5lld %7s %7s %7s %10s\n", label.c_str(),
              r.submitted, r.dropped, r.tracked, r.maps, r.losses, r.init_frames, r.init_busy,
              cell(r.p50_ms, "%.1f").c_str(), cell(r.p99_ms, "%.1f").c_str(),
              cell(r.max_ms, "%.1f").c_str(), cell(r.ate, "%.5f").c_str());
}

}  // namespace

int main(int argc, char** argv) {
  spdlog::set_level(spdlog::level::err);
  ldsm::drivers::setHeapPolicy();  // as `ldsm run` does
  std::string data = LDSM_BENCH_DATA;
  std::string only;
  std::vector<double> speeds = {1.0};
  int rounds = 3;
  bool check = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (ldsm::bench::takeSequenceOption(argc, argv, i, data, only)) {
      continue;
    } else if (a == "--speeds" && i + 1 < argc && !parseSpeeds(argv[i + 1]).empty()) {
      speeds = parseSpeeds(argv[++i]);
    } else if (a == "--rounds" && i + 1 < argc && std::atoi(argv[i + 1]) >= 1 &&
               std::atoi(argv[i + 1]) <= 100) {
      rounds = std::atoi(argv[++i]);
    } else if (a == "--check") {
      check = true;
    } else {
      std::fprintf(stderr,
                   "usage: %s [--data DIR] [--only NAME,...] [--speeds S,... (each in (0, 1000])] "
                   "[--rounds N (1-100)] [--check]\n",
                   argv[0]);
      return 2;
    }
  }
  std::printf("machine: %s; live mode, replayed at the recorded rate times the speed\n",
              ldsm::drivers::machineSummary(ldsm::drivers::describeMachine()).c_str());
  std::printf("%-28s %6s %6s %6s %8s %11s %7s %7s %7s %10s\n", "sequence, speed, round", "frames",
              "drop", "track", "maps/lost", "init/busy", "p50 ms", "p99 ms", "max ms", "ATE [m]");
  bool all_ok = true;
  for (const std::string name : {"kitti00_200", "vamr_desk_loop"}) {
    if (!ldsm::bench::selected(only, name)) continue;
    const std::string folder = data + "/" + name;
    if (!std::filesystem::is_directory(folder)) {
      std::printf("%-28s skipped: %s not found\n", name.c_str(), folder.c_str());
      continue;
    }
    for (const double speed : speeds) {
      std::vector<Result> results;
      for (int round = 1; round <= rounds; ++round) {
        Result r;
        double rss = 0.0;
        const auto status =
            ldsm::bench::runInChild([&](Result& out) { out = runLive(folder, speed); }, r, rss);
        const std::string label = name + " " + cell(speed, "%gx") + " #" + std::to_string(round);
        if (status != ldsm::bench::ChildStatus::kOk) {
          std::printf("%-28s %s\n", label.c_str(),
                      status == ldsm::bench::ChildStatus::kError ? r.error : "crashed");
          all_ok = false;
          continue;
        }
        printRow(label, r);
        results.push_back(r);
      }
      if (results.empty()) continue;
      // Medians of the rounds (counts too: a typical round, not a sum).
      const auto med = [&](auto field) {
        std::vector<double> v;
        for (const Result& r : results) v.push_back(static_cast<double>(r.*field));
        return median(v);
      };
      Result m;
      m.submitted = std::llround(med(&Result::submitted));
      m.dropped = std::llround(med(&Result::dropped));
      m.tracked = std::llround(med(&Result::tracked));
      m.maps = std::llround(med(&Result::maps));
      m.losses = std::llround(med(&Result::losses));
      m.init_frames = std::llround(med(&Result::init_frames));
      m.init_busy = std::llround(med(&Result::init_busy));
      m.p50_ms = med(&Result::p50_ms);
      m.p99_ms = med(&Result::p99_ms);
      m.max_ms = med(&Result::max_ms);
      m.ate = med(&Result::ate);
      printRow(name + " " + cell(speed, "%gx") + " median", m);
      if (speed == 1.0) {
        long long dropped = 0;
        for (const Result& r : results) dropped += r.dropped;
        const bool ok = m.p99_ms <= kTargetP99Ms && dropped == 0;
        all_ok = all_ok && ok;
        std::printf("%-28s target p99 <= %.0f ms, nothing dropped: %s (%lld dropped)\n", "",
                    kTargetP99Ms, ok ? "met" : "MISSED", dropped);
      }
      std::fflush(stdout);
    }
  }
  return check && !all_ok ? 1 : 0;
}
