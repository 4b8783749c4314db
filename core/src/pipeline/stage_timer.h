// Per-stage timing of the pipeline: durations are recorded into fixed-capacity buffers (no
// allocation while running once reserved) and summarised as mean / median / p99 / max. Recording
// and summarising may happen on different threads: a mutex guards the samples, held for one
// record or for one copy of them (the sorting is done outside it).
#pragma once

#include <chrono>
#include <mutex>
#include <string>
#include <vector>

#include "ldsm/system.h"  // StageTiming

namespace ldsm {

class StageTimer {
 public:
  /// Declares the stages up front; `capacity` samples are kept per stage (older ones are
  /// summarised in the mean/max only).
  StageTimer(std::vector<std::string> stages, std::size_t capacity);
  StageTimer(const StageTimer& other);
  StageTimer& operator=(const StageTimer&) = delete;
  void record(int stage, double ms);
  std::vector<StageTiming> summary() const;

  /// Measures one scope into a stage.
  class Scope {
   public:
    Scope(StageTimer& timer, int stage)
        : timer_(timer), stage_(stage), start_(std::chrono::steady_clock::now()) {}
    ~Scope() {
      const auto end = std::chrono::steady_clock::now();
      timer_.record(stage_, std::chrono::duration<double, std::milli>(end - start_).count());
    }
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    StageTimer& timer_;
    int stage_;
    std::chrono::steady_clock::time_point start_;
  };

 private:
  struct Stage {
    std::string name;
    std::vector<double> samples;  ///< ring buffer
    std::size_t next = 0;
    std::int64_t count = 0;
    double sum = 0.0;
    double max = 0.0;
  };
  mutable std::mutex mutex_;
  std::vector<Stage> stages_;
  std::size_t capacity_;
};

}  // namespace ldsm
