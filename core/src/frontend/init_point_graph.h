// Points of the monocular initializer on every pyramid level and the links between them:
// a dense gradient-based selection (the best pixel of each small cell), the k nearest points on the
// same level (for the inverse-depth smoothness term) and, for each point, its nearest point one
// level coarser (its "parent", for coarse-to-fine depth propagation).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "image/gradient_pixel.h"
#include "ldsm/image.h"

namespace ldsm {

/// Appends to `out` (cleared first, capacity reused) the pixel with the largest squared gradient
/// of every cell x cell block of `level`, when that gradient is at least min_gradient (grey levels
/// per pixel). Pixels closer than `margin` to the border are never taken. Returns the count.
int selectBestGradientPerCell(ImageView<const GradientPixel> level, int cell, float min_gradient,
                              int margin, std::vector<Eigen::Vector2f>& out);

/// A bucket grid over 2D points for nearest-neighbour queries. The buckets are square cells of a
/// given size; any number of points may share a bucket.
class PointBucketGrid {
 public:
  /// Buckets `points` (kept by pointer: they must outlive the grid's use) into cells of
  /// `cell` pixels over a width x height area. Positions outside the area are clamped into it.
  void build(const std::vector<Eigen::Vector2f>& points, float cell, int width, int height);

  /// Indices of the (at most) k points nearest to `query`, nearest first, skipping index `skip`
  /// (-1: skip none). Exact. `out` is cleared first; returns its size.
  int nearest(const Eigen::Vector2f& query, int k, int skip, std::vector<int>& out);

 private:
  int bucketX(float x) const;
  int bucketY(float y) const;
  int countInBlock(int bx, int by, int radius, int skip) const;

  const std::vector<Eigen::Vector2f>* points_ = nullptr;
  float inv_cell_ = 1.f;
  int cols_ = 0;
  int rows_ = 0;
  std::vector<int> bucket_start_;  ///< cols*rows+1 offsets into point_index_
  std::vector<int> point_index_;
  std::vector<std::pair<float, int>> scratch_;
};

}  // namespace ldsm
