#include "pipeline/stage_timer.h"

#include <algorithm>

namespace ldsm {

StageTimer::StageTimer(std::vector<std::string> stages, std::size_t capacity)
    : capacity_(capacity) {
  for (auto& s : stages) {
    Stage st;
    st.name = std::move(s);
    st.samples.reserve(capacity);
    stages_.push_back(std::move(st));
  }
}

StageTimer::StageTimer(const StageTimer& other) {
  std::lock_guard<std::mutex> lock(other.mutex_);
  stages_ = other.stages_;
  capacity_ = other.capacity_;
}

void StageTimer::record(int stage, double ms) {
  std::lock_guard<std::mutex> lock(mutex_);
  Stage& s = stages_[static_cast<size_t>(stage)];
  if (s.samples.size() < capacity_) {
    s.samples.push_back(ms);
  } else {
    s.samples[s.next] = ms;
    s.next = (s.next + 1) % capacity_;
  }
  ++s.count;
  s.sum += ms;
  s.max = std::max(s.max, ms);
}

std::vector<StageTiming> StageTimer::summary() const {
  std::vector<Stage> stages;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stages = stages_;
  }
  std::vector<StageTiming> out;
  for (Stage& s : stages) {
    StageTiming t;
    t.stage = s.name;
    t.count = s.count;
    if (s.count > 0) {
      t.mean_ms = s.sum / static_cast<double>(s.count);
      t.max_ms = s.max;
      std::vector<double>& v = s.samples;
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
