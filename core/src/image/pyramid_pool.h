// Image pyramids of one size, recycled: a frame takes one, and it comes back when the frame is
// done with (an ordinary frame after tracking and tracing, a keyframe when it leaves the window).
// Safe to use from the tracking and the mapping thread at once; once enough pyramids circulate,
// nothing is allocated.
#pragma once

#include <memory>
#include <mutex>
#include <vector>

#include "image/image_pyramid.h"

namespace ldsm {

class PyramidPool {
 public:
  PyramidPool(int width, int height, int levels)
      : width_(width), height_(height), levels_(levels) {}

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

  /// Gives a pyramid back (null is ignored). A compacted keyframe's pyramid gets its planes back
  /// here, on the releasing (mapping) side, so that acquire() stays free of allocations.
  void release(std::unique_ptr<ImagePyramid> pyramid) {
    if (!pyramid) return;
    pyramid->expand();
    std::lock_guard<std::mutex> lock(mutex_);
    free_.push_back(std::move(pyramid));
  }

 private:
  int width_, height_, levels_;
  std::mutex mutex_;
  std::vector<std::unique_ptr<ImagePyramid>> free_;
};

}  // namespace ldsm
