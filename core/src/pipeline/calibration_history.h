// The calibration refinement's history over a run, bounded: one sample per fused window until
// the history is full, then every second sample is dropped and only every second window is
// recorded from then on (and so on), so that however long the run, the history holds at most
// `capacity` samples spread evenly over it. Published as an immutable vector (copy on append),
// so that readers of the mapping snapshot never copy it.
#pragma once

#include <memory>
#include <vector>

#include "ldsm/system.h"

namespace ldsm {

class CalibrationHistory {
 public:
  explicit CalibrationHistory(int capacity = SystemStats::kMaxCalibrationSamples);

  /// Records `sample` if its window count is one the current stride keeps (the first window
  /// always is). Samples must come with increasing `windows`; others are ignored.
  void add(const CalibrationSample& sample);

  /// The samples so far, oldest first (never null).
  std::shared_ptr<const std::vector<CalibrationSample>> samples() const { return samples_; }
  /// Windows between recorded samples (1, 2, 4, ...).
  int stride() const { return stride_; }

 private:
  int capacity_;
  int stride_ = 1;
  int last_windows_ = 0;
  std::shared_ptr<const std::vector<CalibrationSample>> samples_;
};

}  // namespace ldsm
