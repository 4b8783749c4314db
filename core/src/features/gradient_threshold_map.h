// The regional gradient threshold of DSO-style point selection: the image is split into square
// blocks, each block gets the median of its gradient magnitudes plus a constant, and the block
// values are smoothed over 3x3 neighbouring blocks so that the threshold varies gently.
#pragma once

#include <cstdint>
#include <vector>

#include "image/gradient_pixel.h"
#include "ldsm/image.h"

namespace ldsm {

class GradientThresholdMap {
 public:
  /// Number of 1-grey-level histogram bins used for the block medians; larger magnitudes land in
  /// the last bin, so medians saturate at kHistogramBins - 0.5.
  static constexpr int kHistogramBins = 64;

  /// Preallocates for width x height level-0 images and square blocks of block_size pixels.
  /// Throws ConfigError when block_size < 1 and InputError when the size is not positive.
  GradientThresholdMap(int width, int height, int block_size);

  /// Recomputes the threshold field from the level-0 gradients (size as at construction; throws
  /// InputError otherwise). Allocates nothing.
  void compute(ImageView<const GradientPixel> gradients, float min_gradient);

  /// Squared smoothed threshold at level-0 pixel (x, y) (inside the image).
  float thresholdSq(int x, int y) const {
    return smoothed_sq_[static_cast<std::size_t>(row_block_[y] * blocks_x_ + col_block_[x])];
  }
  /// The squared thresholds of the blocks of pixel row y, indexed by blockColumns()[x]: for
  /// loops over a row (thresholdSq(x, y) == rowThresholdsSq(y)[blockColumns()[x]]).
  const float* rowThresholdsSq(int y) const {
    return smoothed_sq_.data() + static_cast<std::size_t>(row_block_[y] * blocks_x_);
  }
  /// The block column of each pixel column.
  const int* blockColumns() const { return col_block_.data(); }
  /// Smoothed threshold of block (bx, by), grey levels per pixel.
  float blockThreshold(int bx, int by) const { return smoothed_[by * blocks_x_ + bx]; }
  int blocksX() const { return blocks_x_; }
  int blocksY() const { return blocks_y_; }
  int blockSize() const { return block_size_; }

 private:
  int width_;
  int height_;
  int block_size_;
  int blocks_x_;
  int blocks_y_;
  std::vector<int> col_block_;  ///< block column of each pixel column
  std::vector<int> row_block_;  ///< block row of each pixel row
  std::vector<float> raw_;      ///< median + min_gradient per block
  std::vector<float> smoothed_;
  std::vector<float> smoothed_sq_;
  std::vector<int> histogram_;      ///< kHistogramBins per block column of the current block row
  std::vector<std::int32_t> bins_;  ///< scratch: the histogram bin of each pixel of a row
};

}  // namespace ldsm
