// Image pyramids of one size, recycled: a frame takes one, and it comes back when the frame is
// done with (an ordinary frame after tracking and tracing, a keyframe after it left the window,
// once the newest keyframe is compacted: Mapper::compactNewestImage).
// Safe to use from the tracking and the mapping thread at once; once enough pyramids circulate,
// nothing is allocated.
//
// It keeps at most `max_free` pyramids: more come back at once only when the window lets go of
// several keyframes, and a whole spare pyramid (7.7 MB at 1232x368) is worth keeping only if a
// frame will take it. One thread (deterministic mode) takes one pyramid per frame and gives it
// back before the next, so one spare is enough (kitti00_200: 9 pyramids made in 200 frames
// instead of 8, and the peak heap 3.4 MB lower); the threaded pipeline keeps as many as frames
// can wait for the mapping thread.
#pragma once

#include <algorithm>
#include <cstddef>
#include <memory>
#include <mutex>
#include <vector>

#include "image/image_pyramid.h"

namespace ldsm {

class PyramidPool {
 public:
  /// Pyramids of width x height and `levels` levels; at most `max_free` (at least 1) are kept
  /// for reuse.
  PyramidPool(int width, int height, int levels, std::size_t max_free = 1)
      : width_(width),
        height_(height),
        levels_(levels),
        max_free_(std::max<std::size_t>(max_free, 1)) {}

  /// A pyramid from the pool, or a new one when none is free.
  std::unique_ptr<ImagePyramid> acquire() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!free_.empty()) {
        auto p = std::move(free_.back());
        free_.pop_back();
        return p;
      }
    }
    // Nothing in the pipeline reads |grad I|^2 from the pyramid: leave that plane out (4 of 20
    // bytes per pixel of every keyframe).
    return std::make_unique<ImagePyramid>(width_, height_, levels_, /*with_grad_mag_sq=*/false);
  }

  /// Gives a pyramid back (null is ignored); it is freed when max_free are kept already. A
  /// compacted keyframe's pyramid gets its planes back here, on the releasing (mapping) side, so
  /// that acquire() stays free of allocations.
  void release(std::unique_ptr<ImagePyramid> pyramid) {
    if (!pyramid) return;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (free_.size() >= max_free_) return;  // freed on return, after the lock
    }
    pyramid->expand();
    std::lock_guard<std::mutex> lock(mutex_);
    if (free_.size() < max_free_) free_.push_back(std::move(pyramid));
  }

  /// Pyramids kept for reuse now.
  std::size_t freeCount() {
    std::lock_guard<std::mutex> lock(mutex_);
    return free_.size();
  }

 private:
  int width_, height_, levels_;
  std::size_t max_free_;
  std::mutex mutex_;
  std::vector<std::unique_ptr<ImagePyramid>> free_;
};

}  // namespace ldsm
