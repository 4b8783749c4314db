#include "features/gradient_threshold_map.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "image/gradient_magnitude.h"
#include "ldsm/error.h"

namespace ldsm {

GradientThresholdMap::GradientThresholdMap(int width, int height, int block_size)
    : width_(width), height_(height), block_size_(block_size) {
  if (block_size < 1) {
    throw ConfigError("points.grid_block_size: must be >= 1 (got " + std::to_string(block_size) +
                      ")");
  }
  if (width <= 0 || height <= 0) {
    throw InputError("GradientThresholdMap: image size must be positive (got " +
                     std::to_string(width) + "x" + std::to_string(height) + ")");
  }
  blocks_x_ = (width + block_size - 1) / block_size;
  blocks_y_ = (height + block_size - 1) / block_size;
  col_block_.resize(static_cast<std::size_t>(width));
  row_block_.resize(static_cast<std::size_t>(height));
  for (int x = 0; x < width; ++x) col_block_[static_cast<std::size_t>(x)] = x / block_size;
  for (int y = 0; y < height; ++y) row_block_[static_cast<std::size_t>(y)] = y / block_size;
  const auto blocks = static_cast<std::size_t>(blocks_x_) * static_cast<std::size_t>(blocks_y_);
  raw_.assign(blocks, 0.f);
  smoothed_.assign(blocks, 0.f);
  smoothed_sq_.assign(blocks, 0.f);
  histogram_.assign(static_cast<std::size_t>(blocks_x_) * kHistogramBins, 0);
  bins_.assign(static_cast<std::size_t>(width), 0);
}

void GradientThresholdMap::compute(ImageView<const GradientPixel> gradients, float min_gradient) {
  if (gradients.width != width_ || gradients.height != height_) {
    throw InputError("GradientThresholdMap: gradient image is " + std::to_string(gradients.width) +
                     "x" + std::to_string(gradients.height) + ", expected " +
                     std::to_string(width_) + "x" + std::to_string(height_));
  }
  // Block medians of |grad I| from per-block histograms, one block row at a time. The one-pixel
  // image border (where central differences are undefined and stored as 0) is not counted.
  for (int by = 0; by < blocks_y_; ++by) {
    std::fill(histogram_.begin(), histogram_.end(), 0);
    const int y_begin = std::max(by * block_size_, 1);
    const int y_end = std::min((by + 1) * block_size_, height_ - 1);
    for (int y = y_begin; y < y_end; ++y) {
      simd::gradientMagnitudeBinRow<simd::Vec4>(gradients.row(y) + 1, width_ - 2,
                                                kHistogramBins - 1, bins_.data() + 1);
      for (int x = 1; x < width_ - 1; ++x) {
        ++histogram_[static_cast<std::size_t>(col_block_[static_cast<std::size_t>(x)] *
                                                  kHistogramBins +
                                              bins_[static_cast<std::size_t>(x)])];
      }
    }
    for (int bx = 0; bx < blocks_x_; ++bx) {
      const int* h = histogram_.data() + bx * kHistogramBins;
      int count = 0;
      for (int b = 0; b < kHistogramBins; ++b) count += h[b];
      float median = 0.f;
      if (count > 0) {
        int cumulative = 0;
        for (int b = 0; b < kHistogramBins; ++b) {
          cumulative += h[b];
          if (2 * cumulative >= count) {
            median = static_cast<float>(b) + 0.5f;  // centre of the bin [b, b + 1)
            break;
          }
        }
      }
      raw_[static_cast<std::size_t>(by * blocks_x_ + bx)] = median + min_gradient;
    }
  }
  // 3x3 box smoothing over the blocks that exist.
  for (int by = 0; by < blocks_y_; ++by) {
    for (int bx = 0; bx < blocks_x_; ++bx) {
      float sum = 0.f;
      int n = 0;
      for (int j = std::max(by - 1, 0); j <= std::min(by + 1, blocks_y_ - 1); ++j) {
        for (int i = std::max(bx - 1, 0); i <= std::min(bx + 1, blocks_x_ - 1); ++i) {
          sum += raw_[static_cast<std::size_t>(j * blocks_x_ + i)];
          ++n;
        }
      }
      const float t = sum / static_cast<float>(n);
      smoothed_[static_cast<std::size_t>(by * blocks_x_ + bx)] = t;
      smoothed_sq_[static_cast<std::size_t>(by * blocks_x_ + bx)] = t * t;
    }
  }
}

}  // namespace ldsm
