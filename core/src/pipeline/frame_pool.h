// A fixed pool of preallocated 8-bit grey frame buffers, sized once at start-up (from the
// configuration) and handed out by index: the capture thread acquires a buffer, fills it and
// passes its index (with the frame's metadata, FrameTicket) through a ring; whoever is done with
// it (the tracker, or the capture thread when it drops the frame) releases the index. Acquire and
// release are lock-free, may be called from any thread and never allocate.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "concurrency/backoff.h"
#include "concurrency/mpmc_ring.h"
#include "ldsm/error.h"
#include "ldsm/image.h"

namespace ldsm::pipeline {

/// What travels through the rings: a pool buffer and the frame's metadata.
struct FrameTicket {
  int buffer = -1;          ///< FramePool index
  std::int64_t index = -1;  ///< frame number in the stream
  double timestamp = 0.0;   ///< seconds
  double exposure_ms = std::numeric_limits<double>::quiet_NaN();
  std::int64_t enqueued_ns = 0;  ///< steady_clock time the frame entered the pipeline (latency)
};

class FramePool {
 public:
  /// `count` buffers of width x height (all allocated here). Throws ldsm::ConfigError for a
  /// count outside 1..4096 or a non-positive size.
  FramePool(std::size_t count, int width, int height)
      : images_(checked(count, width, height)),
        in_use_(std::make_unique<std::atomic<bool>[]>(count)),
        free_(concurrency::nextPowerOfTwo(count < 2 ? 2 : count)) {
    for (std::size_t i = 0; i < count; ++i) {
      images_[i].resize(width, height);
      in_use_[i].store(false, std::memory_order_relaxed);
      free_.tryPush(static_cast<int>(i));
    }
  }
  FramePool(const FramePool&) = delete;
  FramePool& operator=(const FramePool&) = delete;

  std::size_t size() const { return images_.size(); }
  int width() const { return images_.front().width(); }
  int height() const { return images_.front().height(); }

  /// Takes a free buffer and returns its index, or -1 when every buffer is in use. When the only
  /// free buffers are being released by another thread at this very moment (the free list's
  /// oldest slot is claimed but not yet written), waits the few instructions that takes.
  int tryAcquire() {
    int index = -1;
    for (concurrency::Backoff backoff; !free_.tryPop(index); backoff.pause())
      if (free_.size() == 0) return -1;
    in_use_[static_cast<std::size_t>(index)].store(true, std::memory_order_relaxed);
    return index;
  }

  /// Gives buffer `index` back. Throws ldsm::Error for an index that is not currently acquired
  /// (out of range, or released twice): a bug in the caller, which would otherwise hand one
  /// buffer to two frames.
  void release(int index) {
    if (index < 0 || static_cast<std::size_t>(index) >= images_.size() ||
        !in_use_[static_cast<std::size_t>(index)].exchange(false, std::memory_order_relaxed))
      throw Error("FramePool::release: buffer " + std::to_string(index) +
                  " is not in use (released twice or never acquired)");
    free_.tryPush(index);  // cannot fail: the free list holds every buffer
  }

  /// The buffer `index` (valid while acquired). Its size is the pool's: resize() within it never
  /// allocates.
  ImageU8& image(int index) { return images_[static_cast<std::size_t>(index)]; }
  const ImageU8& image(int index) const { return images_[static_cast<std::size_t>(index)]; }

  /// Buffers currently free (a snapshot).
  std::size_t freeCount() const { return free_.size(); }

 private:
  static std::size_t checked(std::size_t count, int width, int height) {
    if (count < 1 || count > 4096)
      throw ConfigError("FramePool: buffer count " + std::to_string(count) + " is outside 1..4096");
    if (width <= 0 || height <= 0)
      throw ConfigError("FramePool: frame size " + std::to_string(width) + "x" +
                        std::to_string(height) + " is not positive");
    return count;
  }

  std::vector<ImageU8> images_;
  std::unique_ptr<std::atomic<bool>[]> in_use_;
  concurrency::MpmcRing<int> free_;
};

}  // namespace ldsm::pipeline
