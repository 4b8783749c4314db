// Hands results from the loop-closing worker to the mapper, which collects them at a safe point
// (between keyframes, when no window optimisation is running). The worker may block briefly on
// the lock; the mapper's tryTakeAll() never does (a worker at SCHED_IDLE holding the lock must
// not stall the mapper), it simply finds nothing and looks again at its next safe point.
#pragma once

#include <mutex>
#include <utility>
#include <vector>

namespace ldsm::concurrency {

template <typename T>
class ResultMailbox {
 public:
  /// Worker side: appends a result.
  void post(T value) {
    const std::lock_guard<std::mutex> lock(mutex_);
    pending_.push_back(std::move(value));
  }
  /// Mapper side, never blocks: everything posted so far, oldest first, or nothing when the worker
  /// holds the lock right now (or try_lock fails spuriously); call again later.
  std::vector<T> tryTakeAll() {
    std::vector<T> out;
    std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
    if (lock.owns_lock()) out.swap(pending_);
    return out;
  }
  /// Blocking variant (shutdown, deterministic runs, tests).
  std::vector<T> takeAll() {
    std::vector<T> out;
    const std::lock_guard<std::mutex> lock(mutex_);
    out.swap(pending_);
    return out;
  }

 private:
  std::mutex mutex_;
  std::vector<T> pending_;
};

}  // namespace ldsm::concurrency
