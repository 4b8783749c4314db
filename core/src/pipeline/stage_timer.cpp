#include "pipeline/stage_timer.h"

#include <algorithm>

namespace ldsm {

StageTimer::StageTimer(std::vector<std::string> stages, std::size_t capacity)
    : capacity_(std::max<std::size_t>(1, capacity)) {
  for (auto& name : stages) {
    auto st = std::make_unique<Stage>();
    st->name = std::move(name);
    st->samples = std::make_unique<std::atomic<float>[]>(capacity_);
    for (std::size_t i = 0; i < capacity_; ++i)
      st->samples[i].store(0.f, std::memory_order_relaxed);
    stages_.push_back(std::move(st));
  }
}

void StageTimer::record(int stage, double ms) {
  Stage& s = *stages_[static_cast<std::size_t>(stage)];
  // One recording thread per stage: plain read-modify-write through the atomics.
  const std::int64_t n = s.count.load(std::memory_order_relaxed);
  // Every figure from the sample as kept (in float), so that the percentiles never exceed the
  // maximum.
  const float sample = static_cast<float>(ms);
  s.samples[static_cast<std::size_t>(n) % capacity_].store(sample, std::memory_order_relaxed);
  const double kept = static_cast<double>(sample);
  s.sum.store(s.sum.load(std::memory_order_relaxed) + kept, std::memory_order_relaxed);
  if (kept > s.max.load(std::memory_order_relaxed)) s.max.store(kept, std::memory_order_relaxed);
  s.count.store(n + 1, std::memory_order_release);
}

std::vector<StageTiming> StageTimer::summary() const {
  std::vector<StageTiming> out;
  std::vector<double> v;
  for (const auto& sp : stages_) {
    const Stage& s = *sp;
    StageTiming t;
    t.stage = s.name;
    t.count = s.count.load(std::memory_order_acquire);
    if (t.count > 0) {
      t.mean_ms = s.sum.load(std::memory_order_relaxed) / static_cast<double>(t.count);
      t.max_ms = s.max.load(std::memory_order_relaxed);
      const std::size_t m = std::min(capacity_, static_cast<std::size_t>(t.count));
      v.resize(m);
      for (std::size_t i = 0; i < m; ++i)
        v[i] = static_cast<double>(s.samples[i].load(std::memory_order_relaxed));
      std::sort(v.begin(), v.end());
      t.p50_ms = v[v.size() / 2];
      t.p99_ms =
          v[std::min(v.size() - 1, static_cast<size_t>(0.99 * static_cast<double>(v.size())))];
    }
    out.push_back(t);
  }
  return out;
}

}  // namespace ldsm
