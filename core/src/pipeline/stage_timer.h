// Per-stage timing of the pipeline: durations are recorded into fixed-capacity buffers allocated
// at construction (no allocation while running) and summarised as mean / median / p99 / max.
// Lock-free: the thread that records a stage never waits for one that summarises (stats() may be
// called at any rate), and summary() reads the samples without stopping the recording (a summary
// taken while a stage is being recorded may miss the newest sample).
//
// Threads: each stage is recorded by one thread at a time (different stages may be recorded by
// different threads); summary() from any thread.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "ldsm/system.h"  // StageTiming

namespace ldsm {

class StageTimer {
 public:
  /// The pipeline's stages keep their newest 8192 samples for the percentiles (4.5 minutes of
  /// frames at 30 Hz; 32 KB per stage).
  static constexpr std::size_t kPipelineSamples = 8192;

  /// Declares the stages up front; `capacity` samples are kept per stage (older ones are
  /// summarised in the mean/max only).
  StageTimer(std::vector<std::string> stages, std::size_t capacity);
  StageTimer(const StageTimer&) = delete;
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
    /// Ring buffer of `capacity_` samples in float (a duration to 7 digits; half the memory of
    /// double), filled only as samples come.
    std::unique_ptr<std::atomic<float>[]> samples;
    std::atomic<std::int64_t> count{0};  ///< samples recorded (published)
    std::atomic<double> sum{0.0};
    std::atomic<double> max{0.0};
  };
  std::vector<std::unique_ptr<Stage>> stages_;
  std::size_t capacity_;
};

}  // namespace ldsm
