// The hand-over of tracking references from the mapping stage to the tracking stage. After each
// keyframe (and after initialisation) the mapping stage prepares a coarse tracker for the newest
// keyframe (the window's points projected into it) and publishes it here; before each frame the
// tracking stage adopts the newest one published and hands its previous tracker back for reuse.
// The coarse trackers circulate (two or three are ever allocated); the mutex is held only to swap
// pointers, never while a tracker is prepared or used.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>

#include "frontend/coarse_tracker.h"
#include "math/se3.h"

namespace ldsm {

/// A coarse tracker whose reference is set, with the keyframe it tracks against.
struct PreparedReference {
  std::unique_ptr<CoarseTracker> tracker;
  int keyframe_id = -1;
  SE3d T_c_w;  ///< the keyframe's pose (world -> camera)
  std::int64_t frame_index = -1;
  /// The calibration refinement is still correcting the camera (CalibrationRefinement::settling).
  bool calibration_settling = false;
};

class ReferenceExchange {
 public:
  /// `make` creates a coarse tracker when none is free.
  explicit ReferenceExchange(std::function<std::unique_ptr<CoarseTracker>()> make)
      : make_(std::move(make)) {}

  /// Mapping side: a coarse tracker to prepare (a recycled one when possible).
  std::unique_ptr<CoarseTracker> acquire() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (spare_) return std::move(spare_);
      if (pending_.tracker) {
        // Never adopted: replaced by the one about to be prepared.
        has_pending_.store(false, std::memory_order_relaxed);
        return std::move(pending_.tracker);
      }
    }
    return make_();
  }
  /// Mapping side: makes `ref` the newest reference.
  void publish(PreparedReference ref) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (pending_.tracker && !spare_) spare_ = std::move(pending_.tracker);
    pending_ = std::move(ref);
    has_pending_.store(true, std::memory_order_release);
  }
  /// Tracking side: takes the newest reference when one was published since the last call.
  bool takeNewest(PreparedReference& out) {
    if (!has_pending_.load(std::memory_order_acquire)) return false;
    std::lock_guard<std::mutex> lock(mutex_);
    if (!pending_.tracker) return false;
    out = std::move(pending_);
    pending_ = PreparedReference();
    has_pending_.store(false, std::memory_order_relaxed);
    return true;
  }
  /// Tracking side: gives a coarse tracker back for reuse.
  void recycle(std::unique_ptr<CoarseTracker> tracker) {
    if (!tracker) return;
    std::lock_guard<std::mutex> lock(mutex_);
    if (!spare_) spare_ = std::move(tracker);
  }
  /// Drops a published reference that was not adopted (tracking lost).
  void clear() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (pending_.tracker && !spare_) spare_ = std::move(pending_.tracker);
    pending_ = PreparedReference();
    has_pending_.store(false, std::memory_order_relaxed);
  }

 private:
  std::function<std::unique_ptr<CoarseTracker>()> make_;
  std::mutex mutex_;
  std::atomic<bool> has_pending_{false};
  PreparedReference pending_;
  std::unique_ptr<CoarseTracker> spare_;
};

}  // namespace ldsm
