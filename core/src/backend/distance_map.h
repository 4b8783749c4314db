// The spacing test of point activation: the city-block distance from every level-1 pixel to the
// nearest point already in the newest keyframe.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace ldsm {

/// City-block distance (level-1 pixels) to the nearest occupied cell. The marks of one
/// activation round are spread by a two-pass distance transform (forward and backward raster
/// scans: exact for the city-block metric on an open grid, the same values a breadth-first search
/// gives, in a few instructions per cell); cells marked later count as occupied (distance 0) at
/// once, without spreading.
class DistanceMap {
 public:
  DistanceMap() = default;
  DistanceMap(int w, int h) { reset(w, h); }
  /// A w x h map with no cell marked. Keeps its memory when it is large enough (the mapper resets
  /// one map at every keyframe instead of allocating an image-sized one).
  void reset(int w, int h) {
    w_ = w;
    h_ = h;
    d_.assign(static_cast<std::size_t>(w) * h, kFar);
  }
  void mark(float u0, float v0) {
    const int x = static_cast<int>(u0 * 0.5f + 0.5f), y = static_cast<int>(v0 * 0.5f + 0.5f);
    if (x < 0 || y < 0 || x >= w_ || y >= h_) return;
    d_[static_cast<std::size_t>(y) * w_ + x] = 0;
  }
  /// Every cell's distance to the nearest marked cell (kFar when none is marked).
  void propagate() {
    int* d = d_.data();
    for (int y = 0; y < h_; ++y) {
      int* row = d + static_cast<std::size_t>(y) * w_;
      const int* up = y > 0 ? row - w_ : nullptr;
      for (int x = 0; x < w_; ++x) {
        int v = row[x];
        if (x > 0) v = std::min(v, row[x - 1] + 1);
        if (up != nullptr) v = std::min(v, up[x] + 1);
        row[x] = v;
      }
    }
    for (int y = h_ - 1; y >= 0; --y) {
      int* row = d + static_cast<std::size_t>(y) * w_;
      const int* down = y + 1 < h_ ? row + w_ : nullptr;
      for (int x = w_ - 1; x >= 0; --x) {
        int v = row[x];
        if (x + 1 < w_) v = std::min(v, row[x + 1] + 1);
        if (down != nullptr) v = std::min(v, down[x] + 1);
        row[x] = v;
      }
    }
  }
  int at(float u0, float v0) const {
    const int x = static_cast<int>(u0 * 0.5f + 0.5f), y = static_cast<int>(v0 * 0.5f + 0.5f);
    if (x < 0 || y < 0 || x >= w_ || y >= h_) return -1;
    return d_[static_cast<std::size_t>(y) * w_ + x];
  }

 private:
  static constexpr int kFar = 1 << 20;
  int w_ = 0, h_ = 0;
  std::vector<int> d_;
};

}  // namespace ldsm
