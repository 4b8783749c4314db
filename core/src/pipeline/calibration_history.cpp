#include "pipeline/calibration_history.h"

#include <algorithm>

namespace ldsm {

CalibrationHistory::CalibrationHistory(int capacity)
    : capacity_(std::max(capacity, 2)),
      samples_(std::make_shared<const std::vector<CalibrationSample>>()) {}

void CalibrationHistory::add(const CalibrationSample& sample) {
  if (sample.windows <= last_windows_) return;
  last_windows_ = sample.windows;
  if ((sample.windows - 1) % stride_ != 0) return;
  auto next = std::make_shared<std::vector<CalibrationSample>>();
  next->reserve(static_cast<size_t>(capacity_));
  if (static_cast<int>(samples_->size()) < capacity_) {
    *next = *samples_;
  } else {
    // Full: keep every second sample (windows 1, 1 + 2 stride, ...) and record half as often.
    for (size_t i = 0; i < samples_->size(); i += 2) next->push_back((*samples_)[i]);
    stride_ *= 2;
    if ((sample.windows - 1) % stride_ != 0) {
      samples_ = std::move(next);
      return;
    }
  }
  next->push_back(sample);
  samples_ = std::move(next);
}

}  // namespace ldsm
