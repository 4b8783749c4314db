#include "frontend/init_point_graph.h"

#include <algorithm>
#include <cmath>

namespace ldsm {

int selectBestGradientPerCell(ImageView<const GradientPixel> level, int cell, float min_gradient,
                              int margin, std::vector<Eigen::Vector2f>& out) {
  out.clear();
  if (cell < 1 || level.empty()) return 0;
  const int x_begin = margin;
  const int y_begin = margin;
  const int x_end = level.width - margin;
  const int y_end = level.height - margin;
  const float min_sq = min_gradient * min_gradient;
  for (int cy = y_begin; cy < y_end; cy += cell) {
    const int cy_end = std::min(cy + cell, y_end);
    for (int cx = x_begin; cx < x_end; cx += cell) {
      const int cx_end = std::min(cx + cell, x_end);
      float best = min_sq;
      int best_x = -1;
      int best_y = -1;
      for (int y = cy; y < cy_end; ++y) {
        const GradientPixel* row = level.row(y);
        for (int x = cx; x < cx_end; ++x) {
          const float g = row[x].dx * row[x].dx + row[x].dy * row[x].dy;
          if (g >= best) {
            best = g;
            best_x = x;
            best_y = y;
          }
        }
      }
      if (best_x >= 0) out.emplace_back(static_cast<float>(best_x), static_cast<float>(best_y));
    }
  }
  return static_cast<int>(out.size());
}

void PointBucketGrid::build(const std::vector<Eigen::Vector2f>& points, float cell, int width,
                            int height) {
  points_ = &points;
  inv_cell_ = 1.f / std::max(cell, 1e-3f);
  cols_ = std::max(1, static_cast<int>(std::ceil(static_cast<float>(width) * inv_cell_)));
  rows_ = std::max(1, static_cast<int>(std::ceil(static_cast<float>(height) * inv_cell_)));
  bucket_start_.assign(static_cast<std::size_t>(cols_) * rows_ + 1, 0);
  for (const Eigen::Vector2f& p : points) {
    ++bucket_start_[static_cast<std::size_t>(bucketY(p.y()) * cols_ + bucketX(p.x())) + 1];
  }
  for (std::size_t i = 1; i < bucket_start_.size(); ++i) bucket_start_[i] += bucket_start_[i - 1];
  point_index_.resize(points.size());
  std::vector<int> fill(bucket_start_.begin(), bucket_start_.end() - 1);
  for (int i = 0; i < static_cast<int>(points.size()); ++i) {
    const Eigen::Vector2f& p = points[static_cast<std::size_t>(i)];
    point_index_[static_cast<std::size_t>(
        fill[static_cast<std::size_t>(bucketY(p.y()) * cols_ + bucketX(p.x()))]++)] = i;
  }
}

int PointBucketGrid::bucketX(float x) const {
  return std::clamp(static_cast<int>(std::floor(x * inv_cell_)), 0, cols_ - 1);
}

int PointBucketGrid::bucketY(float y) const {
  return std::clamp(static_cast<int>(std::floor(y * inv_cell_)), 0, rows_ - 1);
}

int PointBucketGrid::countInBlock(int bx, int by, int radius, int skip) const {
  int count = 0;
  const int y0 = std::max(0, by - radius), y1 = std::min(rows_ - 1, by + radius);
  const int x0 = std::max(0, bx - radius), x1 = std::min(cols_ - 1, bx + radius);
  for (int y = y0; y <= y1; ++y) {
    const int row = y * cols_;
    count += bucket_start_[static_cast<std::size_t>(row + x1) + 1] -
             bucket_start_[static_cast<std::size_t>(row + x0)];
  }
  // The skipped point is counted when it lies in the block; it always lies in its own bucket.
  if (skip >= 0) {
    const Eigen::Vector2f& s = (*points_)[static_cast<std::size_t>(skip)];
    const int sx = bucketX(s.x()), sy = bucketY(s.y());
    if (sx >= x0 && sx <= x1 && sy >= y0 && sy <= y1) --count;
  }
  return count;
}

int PointBucketGrid::nearest(const Eigen::Vector2f& query, int k, int skip, std::vector<int>& out) {
  out.clear();
  if (points_ == nullptr || k <= 0 || points_->empty()) return 0;
  const int bx = bucketX(query.x());
  const int by = bucketY(query.y());
  const int max_radius = std::max(cols_, rows_);
  // Smallest block holding k candidates: they all lie within (radius + 1) * sqrt(2) cells of the
  // query, so every closer point lies in the block of radius ceil((radius + 1) * sqrt(2)).
  int radius = 0;
  while (radius < max_radius && countInBlock(bx, by, radius, skip) < k) ++radius;
  const int search =
      std::min(max_radius, static_cast<int>(std::ceil(static_cast<float>(radius + 1) * 1.41422f)));

  scratch_.clear();
  const int y0 = std::max(0, by - search), y1 = std::min(rows_ - 1, by + search);
  const int x0 = std::max(0, bx - search), x1 = std::min(cols_ - 1, bx + search);
  for (int y = y0; y <= y1; ++y) {
    const int row = y * cols_;
    const int begin = bucket_start_[static_cast<std::size_t>(row + x0)];
    const int end = bucket_start_[static_cast<std::size_t>(row + x1) + 1];
    for (int j = begin; j < end; ++j) {
      const int idx = point_index_[static_cast<std::size_t>(j)];
      if (idx == skip) continue;
      scratch_.emplace_back(((*points_)[static_cast<std::size_t>(idx)] - query).squaredNorm(), idx);
    }
  }
  const std::size_t n = std::min(scratch_.size(), static_cast<std::size_t>(k));
  std::partial_sort(scratch_.begin(), scratch_.begin() + static_cast<std::ptrdiff_t>(n),
                    scratch_.end());
  for (std::size_t i = 0; i < n; ++i) out.push_back(scratch_[i].second);
  return static_cast<int>(out.size());
}

}  // namespace ldsm
