// A long revisiting run, pass by pass: a sequence made by scripts/pingpong-sequence.sh (a real
// sequence played forward and backward N times) through the System, with per pass the ATE of
// that pass (its own Sim(3) alignment) and of everything so far, keyframes (made, kept with data),
// map points, resident memory (RSS, and the live heap: RSS also holds freed memory the allocator
// keeps) and the latency of the pass. What map reuse must keep bounded:
// after the first pass, memory should hardly grow.
//
//   bench_soak --dataset DIR --frames-per-pass K [--realtime | --threaded] [--no-reuse] [--no-loop]
//              [--config FILE]   (a configuration YAML as `ldsm run --config` takes)
//              [--log-level L]   (spdlog level, default warn; debug shows reuse decisions)
//              [--trajectory FILE] (all frame poses at the end, TUM format)
//
// Under each pass a second line says what map reuse and loop closure did in it: map keyframes
// brought back and taken out, candidates checked and those turned down by the geometric, the ORB
// and the direct check, keyframes culled as redundant, reuse-triggered corrections, loops closed
// and how many moved keyframes; a third line the pass's mean ms per call of the stages whose cost
// could grow with the map (track per frame, mapping/reuse/loop per keyframe). A pass that keeps
// new keyframes while bringing none back has lost the map.
//
// Default: deterministic, one thread, as fast as possible. --realtime: the live pipeline
// (threaded, frames dropped when tracking is behind) paced at the recorded frame rate.
// --threaded: the threaded pipeline offline (not paced, nothing dropped).
#include <spdlog/spdlog.h>

#include <malloc.h>
#include <unistd.h>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "bench_input.h"
#include "ldsm/drivers/allocator_policy.h"
#include "ldsm/drivers/config_yaml.h"
#include "ldsm/drivers/machine_info.h"
#include "ldsm/drivers/trajectory_io.h"
#include "ldsm/drivers/trajectory_spill.h"
#include "ldsm/eval/ate.h"

namespace {

double residentMb() {
  std::ifstream in("/proc/self/statm");
  long pages = 0, resident = 0;
  in >> pages >> resident;
  return static_cast<double>(resident) * static_cast<double>(sysconf(_SC_PAGESIZE)) / (1 << 20);
}

/// Bytes the allocator has handed out and not got back (glibc): the live heap, without the freed
/// memory it keeps for reuse, which RSS counts.
double liveHeapMb() {
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
  const struct mallinfo2 m = mallinfo2();
  return static_cast<double>(m.uordblks + m.hblkhd) / (1 << 20);
#else
  return NAN;
#endif
}

ldsm::Trajectory between(const ldsm::Trajectory& t, double t0, double t1) {
  ldsm::Trajectory out;
  for (const auto& p : t)
    if (p.timestamp >= t0 && p.timestamp < t1) out.push_back(p);
  return out;
}

double ate(const ldsm::Trajectory& gt, const ldsm::Trajectory& est) {
  if (est.size() < 3 || gt.size() < 3) return NAN;
  try {
    return ldsm::eval::computeAte(gt, est).rmse;
  } catch (const std::exception&) {
    return NAN;
  }
}

}  // namespace

int main(int argc, char** argv) {
  ldsm::drivers::setHeapPolicy();  // as `ldsm run` does
  std::string dataset;
  std::int64_t per_pass = 0;
  bool realtime = false, reuse = true, loop = true;
  // Threaded like --realtime, but offline: as fast as possible and nothing dropped (the threaded
  // code paths without the timing of a live run, e.g. under a heap profiler).
  bool threaded = false;
  // Leaves without tearing the system down, so that a heap profiler (heaptrack --print-leaks)
  // reports what is still allocated at the end of the run; two runs of different length compared
  // show what grows.
  bool exit_without_teardown = false;
  std::string config_path;
  std::string trajectory_path;
  std::string log_level = "warn";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--dataset" && i + 1 < argc) {
      dataset = argv[++i];
    } else if (a == "--frames-per-pass" && i + 1 < argc) {
      per_pass = std::stoll(argv[++i]);
    } else if (a == "--realtime") {
      realtime = true;
    } else if (a == "--threaded") {
      threaded = true;
    } else if (a == "--no-reuse") {
      reuse = false;
    } else if (a == "--no-loop") {
      loop = false;
    } else if (a == "--config" && i + 1 < argc) {
      config_path = argv[++i];
    } else if (a == "--trajectory" && i + 1 < argc) {
      trajectory_path = argv[++i];
    } else if (a == "--log-level" && i + 1 < argc) {
      log_level = argv[++i];
    } else if (a == "--exit-without-teardown") {
      exit_without_teardown = true;
    } else {
      std::fprintf(
          stderr,
          "usage: %s --dataset DIR --frames-per-pass K [--realtime | --threaded] [--no-reuse] "
          "[--no-loop] [--config FILE] [--log-level L] [--trajectory FILE] "
          "[--exit-without-teardown]\n",
          argv[0]);
      return 2;
    }
  }
  if (dataset.empty() || per_pass <= 0) {
    std::fprintf(stderr, "bench_soak: --dataset and --frames-per-pass are required\n");
    return 2;
  }
  spdlog::set_level(spdlog::level::from_str(log_level));
  std::printf("machine: %s\n",
              ldsm::drivers::machineSummary(ldsm::drivers::describeMachine()).c_str());
  ldsm::Config config =
      config_path.empty() ? ldsm::Config{} : ldsm::drivers::loadConfigYaml(config_path);
  config.system.deterministic = !realtime && !threaded;
  config.system.live = realtime;
  config.reuse.enabled = reuse;
  config.loop.enabled = loop;
  ldsm::bench::BenchInput in = ldsm::bench::openBenchInput(config, dataset, "");
  std::printf("%s, %s, reuse %s, loop closure %s\n", dataset.c_str(),
              realtime   ? "real time, threaded"
              : threaded ? "threaded, offline"
                         : "deterministic",
              reuse ? "on" : "off", loop ? "on" : "off");
  std::printf("%4s %8s %10s %10s %9s %9s %10s %11s %9s %9s %9s\n", "pass", "frames", "ATE pass",
              "ATE all", "keyframes", "kf data", "points", "graph v/e", "RSS MB", "heap MB",
              "ms/frame");
  ldsm::drivers::Frame f;
  std::int64_t n = 0;
  double pass_start_t = -1.0;
  auto wall0 = std::chrono::steady_clock::now();
  auto pass_wall = wall0;
  ldsm::ReuseStats last_reuse;
  std::int64_t last_loops = 0;
  std::vector<ldsm::StageTiming> last_stages;
  // Frames beyond system.frame_history (by default 9000 in the live mode of --realtime) leave
  // the engine's memory: they go to a file here, so that this process's memory stays the
  // engine's. "ATE all" is then left out until the end (it would read them back every pass).
  ldsm::drivers::TrajectorySpill spill((std::filesystem::temp_directory_path() /
                                        ("ldsm-bench-soak-" + std::to_string(::getpid()) + ".bin"))
                                           .string());
  const auto report = [&](std::int64_t pass, double t_end) {
    in.system->finish();
    const ldsm::SystemStats s = in.system->stats();
    const double rss = residentMb(), heap = liveHeapMb();
    spill.append(in.system->takeRetiredFrames());
    const ldsm::Trajectory est = in.system->trajectory();
    const auto now = std::chrono::steady_clock::now();
    const double ms = std::chrono::duration<double, std::milli>(now - pass_wall).count() /
                      static_cast<double>(per_pass);
    pass_wall = now;
    const std::string graph =
        std::to_string(s.map.pose_graph_vertices) + "/" + std::to_string(s.map.pose_graph_edges);
    std::printf(
        "%4lld %8lld %10s %10s %9lld %9lld %10lld %11s %9.1f %9.1f %9.2f\n",
        static_cast<long long>(pass), static_cast<long long>(s.frames),
        ldsm::bench::cell(
            ate(between(in.ground_truth, pass_start_t, t_end), between(est, pass_start_t, t_end)),
            "%.5f")
            .c_str(),
        spill.size() > 0 ? "-" : ldsm::bench::cell(ate(in.ground_truth, est), "%.5f").c_str(),
        static_cast<long long>(s.keyframes), static_cast<long long>(s.map.data_keyframes),
        static_cast<long long>(s.map.points), graph.c_str(), rss, heap, ms);
    const ldsm::ReuseStats& r = s.reuse;
    // stats().loops holds the newest events only: this pass's are its last ones.
    const std::int64_t loops = s.loops_closed - last_loops;
    int applied = 0;
    const std::size_t listed =
        std::min<std::size_t>(s.loops.size(), static_cast<std::size_t>(loops));
    for (std::size_t i = s.loops.size() - listed; i < s.loops.size(); ++i)
      if (s.loops[i].corrected_keyframes > 0) ++applied;
    std::printf(
        "     reuse +%lld -%lld, %lld candidates checked, turned down %lld geometry %lld ORB %lld "
        "direct, culled %lld, map corrections %lld; loops %lld (%d moved keyframes)\n",
        static_cast<long long>(r.reactivations - last_reuse.reactivations),
        static_cast<long long>(r.deactivations - last_reuse.deactivations),
        static_cast<long long>(r.candidates_checked - last_reuse.candidates_checked),
        static_cast<long long>(r.rejected_geometry - last_reuse.rejected_geometry),
        static_cast<long long>(r.rejected_features - last_reuse.rejected_features),
        static_cast<long long>(r.rejected_photometric - last_reuse.rejected_photometric),
        static_cast<long long>(r.culled_keyframes - last_reuse.culled_keyframes),
        static_cast<long long>(r.map_corrections - last_reuse.map_corrections),
        static_cast<long long>(loops), applied);
    // This pass's stage times: ms per call of the stages whose cost may grow with the map.
    std::string stages;
    for (const ldsm::StageTiming& t : s.stages) {
      if (t.stage != "track" && t.stage != "mapping" && t.stage != "reuse" && t.stage != "loop")
        continue;
      double before_ms = 0.0;
      std::int64_t before = 0;
      for (const ldsm::StageTiming& l : last_stages)
        if (l.stage == t.stage) {
          before = l.count;
          before_ms = l.mean_ms * static_cast<double>(l.count);
        }
      const std::int64_t calls = t.count - before;
      if (calls <= 0) continue;
      stages += ldsm::bench::cell(
          (t.mean_ms * static_cast<double>(t.count) - before_ms) / static_cast<double>(calls),
          (" " + t.stage + " %.2f").c_str());
    }
    std::printf("     ms per call:%s\n", stages.c_str());
    last_stages = s.stages;
    last_reuse = r;
    last_loops = s.loops_closed;
    std::fflush(stdout);
  };
  double first_t = 0.0;
  while (in.source->next(f)) {
    if (n == 0) first_t = f.timestamp;
    if (pass_start_t < 0.0) pass_start_t = f.timestamp;
    if (realtime) {
      const double due = f.timestamp - first_t;
      const double now =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
      if (due > now) std::this_thread::sleep_for(std::chrono::duration<double>(due - now));
    }
    in.system->submit({f.image.view(), f.timestamp, f.exposure_ms});
    ++n;
    if (n % per_pass == 0) {
      report(n / per_pass, f.timestamp + 1e-9);
      pass_start_t = -1.0;
    }
  }
  if (n % per_pass != 0) report(n / per_pass + 1, 1e300);
  const ldsm::SystemStats s = in.system->stats();
  for (const auto& l : s.latency)
    if (l.stage == "submit_to_tracked")
      std::printf("pose latency (submit -> tracked): p50 %.1f ms, p99 %.1f ms; dropped %lld\n",
                  l.p50_ms, l.p99_ms, static_cast<long long>(s.dropped_frames));
  std::printf("reuse: %lld reactivations, %lld culled keyframes, %.1f KB per kept keyframe\n",
              static_cast<long long>(s.reuse.reactivations),
              static_cast<long long>(s.reuse.culled_keyframes), s.map.bytes_per_keyframe / 1024.0);
  if (spill.size() > 0) {
    spill.append(in.system->takeRetiredFrames());
    const ldsm::Trajectory all = spill.read(in.system->trajectory());
    std::printf(
        "all passes: ATE %.5f m over %zu frame poses (%lld left the engine's memory, %lld "
        "of them lost)\n",
        ate(in.ground_truth, all), all.size(), static_cast<long long>(s.retired_frames),
        static_cast<long long>(s.lost_retired_frames));
    if (!trajectory_path.empty()) ldsm::drivers::writeTumTrajectory(trajectory_path, all);
  } else if (!trajectory_path.empty()) {
    ldsm::drivers::writeTumTrajectory(trajectory_path, in.system->trajectory());
  }
  spill.remove();
  if (exit_without_teardown) {
    std::fflush(stdout);
    std::_Exit(0);
  }
  return 0;
}
