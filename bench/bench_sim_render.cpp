// Synthetic scene rendering speed: frames per second of SimSource::renderFrame (irradiance,
// anti-aliasing, image formation) at 640x480 on one core, per scene and setting.
// Run: build/bench/bench_sim_render [--benchmark_filter=loop]
#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <string>

#include "ldsm/drivers/sim/sim_source.h"

namespace {

using ldsm::drivers::sim::SimOptions;
using ldsm::drivers::sim::SimScene;
using ldsm::drivers::sim::SimSource;

std::shared_ptr<const SimScene> scene(const std::string& name) {
  static std::map<std::string, std::shared_ptr<const SimScene>> cache;
  auto& s = cache[name];
  if (!s) s = std::make_shared<const SimScene>(ldsm::drivers::sim::makeSimScene(name));
  return s;
}

// Renders frames spread over the whole sequence (stride 7, wrapping).
void renderFrames(benchmark::State& state, const std::string& name, const SimOptions& options) {
  SimSource source(scene(name), options);
  ldsm::drivers::Frame frame;
  std::int64_t i = 0;
  for (auto _ : state) {
    source.renderFrame(i, frame);
    benchmark::DoNotOptimize(frame.image.data());
    i = (i + 7) % source.frameCount();
  }
  state.counters["fps"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_SimDefault(benchmark::State& state, const char* name) {
  renderFrames(state, name, SimOptions{});
}

void BM_SimNoAntialiasing(benchmark::State& state, const char* name) {
  SimOptions o;
  o.antialias_edges = false;
  renderFrames(state, name, o);
}

void BM_SimSupersampling2(benchmark::State& state, const char* name) {
  SimOptions o;
  o.supersampling = 2;
  renderFrames(state, name, o);
}

void BM_SimAllEffects(benchmark::State& state, const char* name) {
  SimOptions o;
  o.exposure_changes = true;
  o.noise_sigma = 2.0;
  o.response = ldsm::drivers::sim::SimResponse::SCurve;
  renderFrames(state, name, o);
}

void BM_SimSceneBuild(benchmark::State& state, const char* name) {
  for (auto _ : state) {
    SimScene s = ldsm::drivers::sim::makeSimScene(name);
    benchmark::DoNotOptimize(s.quads.data());
  }
}

}  // namespace

BENCHMARK_CAPTURE(BM_SimDefault, loop, "loop")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SimDefault, forward, "forward")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SimDefault, rotation, "rotation")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SimDefault, short, "short")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SimNoAntialiasing, loop, "loop")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SimAllEffects, loop, "loop")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SimSupersampling2, loop, "loop")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SimSceneBuild, loop, "loop")->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
