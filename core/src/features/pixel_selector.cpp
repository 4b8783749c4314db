#include "features/pixel_selector.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "image/gradient_magnitude.h"
#include "ldsm/error.h"
#include "math/constants.h"

namespace ldsm {
namespace {

constexpr int kDirections = 16;
/// Weight of |grad I|^2 next to the squared directional component in a candidate's score.
constexpr float kMagnitudeWeight = 0.25f;
/// The cell size never shrinks below the initial guess divided by this (bounds the pick count).
constexpr float kMaxCellShrink = 4.f;

/// A fixed hash of a cell (and level) to one of the kDirections score directions.
inline unsigned cellHash(int cx, int cy, int level) {
  unsigned h = static_cast<unsigned>(cx) * 73856093u ^ static_cast<unsigned>(cy) * 19349663u ^
               static_cast<unsigned>(level + 1) * 83492791u;
  h ^= h >> 13;
  h *= 0x5bd1e995u;
  h ^= h >> 15;
  return h % kDirections;
}

void checkConfig(const PointSelectionConfig& c) {
  if (c.points_per_keyframe < 1) {
    throw ConfigError("points.points_per_keyframe: must be >= 1 (got " +
                      std::to_string(c.points_per_keyframe) + ")");
  }
  if (!(c.corner_fraction >= 0.0 && c.corner_fraction <= 1.0)) {
    throw ConfigError("points.corner_fraction: must be in [0, 1] (got " +
                      std::to_string(c.corner_fraction) + ")");
  }
  if (!(c.min_gradient >= 0.0 && std::isfinite(c.min_gradient))) {
    throw ConfigError("points.min_gradient: must be finite and >= 0 (got " +
                      std::to_string(c.min_gradient) + ")");
  }
  if (c.clipped_margin < 0) {
    throw ConfigError("points.clipped_margin: must be >= 0 (got " +
                      std::to_string(c.clipped_margin) + ")");
  }
}

}  // namespace

PixelSelector::PixelSelector(int width, int height, const PointSelectionConfig& config)
    : width_(width),
      height_(height),
      config_((checkConfig(config), config)),
      thresholds_(width, height, config.grid_block_size),
      corner_detector_(width, height) {
  blocked_.resize(width, height);
  magnitude_sq_.assign(static_cast<std::size_t>(std::max(width, 0)), 0.f);
  near_clipped_rows_.resize(static_cast<std::size_t>(2 * std::max(config_.clipped_margin, 0) + 1) *
                            static_cast<std::size_t>(std::max(width, 0)));
  near_clipped_.resize(width, height);
  last_clipped_.resize(static_cast<std::size_t>(std::max(height, 0)));
  for (int i = 0; i < kDirections; ++i) {
    // Half-turn is enough: the score uses the squared component.
    const double angle = kPi * i / kDirections;
    dir_x_[i] = static_cast<float>(std::cos(angle));
    dir_y_[i] = static_cast<float>(std::sin(angle));
  }
  const int max_corners =
      static_cast<int>(std::lround(config.corner_fraction * config.points_per_keyframe));
  corners_.reserve(static_cast<std::size_t>(max_corners));
  // Enough for every cell of the finest grid the adaptation can reach at density 1.
  const double region_w = std::max(width - 2 * kBorder, 0);
  const double region_h = std::max(height - 2 * kBorder, 0);
  const double min_cell =
      std::max(1.0, std::sqrt(region_w * region_h / config.points_per_keyframe) / kMaxCellShrink);
  const auto cells = static_cast<std::size_t>((std::ceil(region_w / min_cell) + 1) *
                                              (std::ceil(region_h / min_cell) + 1));
  pass_picks_.reserve(cells);
  best_picks_.reserve(cells);
}

int PixelSelector::select(const ImagePyramid& pyramid, float density_factor,
                          std::vector<SelectedPixel>& out, const CornerLimits& more,
                          std::vector<Corner>* more_out) {
  if (pyramid.levels() < 1 || pyramid.width(0) != width_ || pyramid.height(0) != height_) {
    throw InputError(
        "PixelSelector: pyramid is " +
        (pyramid.levels() < 1
             ? std::string("empty")
             : std::to_string(pyramid.width(0)) + "x" + std::to_string(pyramid.height(0))) +
        ", the selector was made for " + std::to_string(width_) + "x" + std::to_string(height_));
  }
  if (!(density_factor > 0.f) || !std::isfinite(density_factor)) {
    throw InputError("PixelSelector: density_factor must be finite and > 0 (got " +
                     std::to_string(density_factor) + ")");
  }
  out.clear();
  const ImageView<const GradientPixel> grad0 = pyramid.gradients(0);
  const int target =
      std::max(1, static_cast<int>(std::lround(static_cast<double>(config_.points_per_keyframe) *
                                               static_cast<double>(density_factor))));

  // 1. Corners, strongest first.
  CornerParams corner_params;
  corner_params.max_corners = static_cast<int>(std::lround(config_.corner_fraction * target));
  corner_params.min_score =
      std::max(static_cast<float>(config_.min_gradient * config_.min_gradient), 1.f);
  corner_params.min_distance = kCornerMinDistance;
  corner_params.border = kCornerBorder;
  corner_detector_.detect(grad0, corner_params, corners_);
  if (more_out != nullptr) {
    CornerParams more_params = corner_params;
    more_params.max_corners = more.max_corners;
    more_params.min_score = more.min_score;
    if (corner_params.max_corners > 0)
      corner_detector_.reselect(more_params, *more_out);
    else
      corner_detector_.detect(grad0, more_params, *more_out);
  }
  markNearClipped(pyramid.clipped());
  dropCornersNearClipped();
  blockAroundCorners();

  // 2. Gradient points on the adaptive grid.
  thresholds_.compute(grad0, static_cast<float>(config_.min_gradient));
  markBelowThreshold(grad0);
  num_levels_ = std::min(pyramid.levels(), static_cast<int>(levels_.size()));
  float factor = 1.f;
  for (int l = 0; l < num_levels_; ++l) {
    levels_[l] = {pyramid.gradients(l), factor * factor};
    factor *= kCoarseThresholdFactor;
  }
  const int grid_target = target - static_cast<int>(corners_.size());
  const int region_w = width_ - 2 * kBorder;
  const int region_h = height_ - 2 * kBorder;
  best_picks_.clear();
  last_cell_size_ = 0.f;
  if (grid_target > 0 && region_w > 0 && region_h > 0) {
    const float area = static_cast<float>(region_w) * static_cast<float>(region_h);
    const float initial = std::sqrt(area / static_cast<float>(grid_target));
    const float min_cell = std::max(1.f, initial / kMaxCellShrink);
    const float max_cell = static_cast<float>(std::max(region_w, region_h));
    float cell = std::clamp(initial, min_cell, max_cell);
    int best_error = -1;
    for (int pass = 0; pass < kMaxPasses; ++pass) {
      const int n = gridPass(cell, pass_picks_);
      const int error = std::abs(n - grid_target);
      if (best_error < 0 || error < best_error) {
        best_error = error;
        best_picks_.swap(pass_picks_);
        last_cell_size_ = cell;
      }
      if (static_cast<float>(error) <= kCountTolerance * static_cast<float>(grid_target)) break;
      const float next = n == 0 ? min_cell
                                : std::clamp(cell * std::sqrt(static_cast<float>(n) / grid_target),
                                             min_cell, max_cell);
      if (std::abs(next - cell) < 1e-3f) break;
      cell = next;
    }
  }

  // 3. Corners first, then the grid points, thinned out uniformly if there are too many.
  for (const Corner& c : corners_) out.push_back({c.u, c.v, 0, true, c.score});
  const int n = static_cast<int>(best_picks_.size());
  const int keep = std::max(std::min(n, grid_target), 0);
  long long acc = 0;
  for (int i = 0; i < n; ++i) {
    acc += keep;
    if (acc >= n) {
      acc -= n;
      const SelectedPixel& p = best_picks_[i];
      if (!near_clipped_(static_cast<int>(p.u), static_cast<int>(p.v))) out.push_back(p);
    }
  }
  return static_cast<int>(out.size());
}

void PixelSelector::markNearClipped(ImageView<const std::uint8_t> clipped) {
  const int r = config_.clipped_margin;
  // The sizes as locals: the byte stores below could alias the members (char aliasing), which
  // would reload them every iteration and keep the loops from vectorising.
  const int w = width_, h = height_;
  if (w <= 0 || h <= 0) return;
  const auto row_bytes = static_cast<std::size_t>(w);
  int* last_clipped = last_clipped_.data();
  // A pixel is near when a clipped pixel lies within r in x and in y: the union of the shifted
  // masks, first along the rows, then along the columns (byte loops the compiler vectorises).
  // Most rows have no clipped pixel at all (last_clipped[y] < 0 marks them). The rows' union is
  // made for row y + r just before row y needs it, into a ring of 2r + 1 rows.
  for (int y = 0; y < h; ++y) {
    const std::uint8_t* in = clipped.row(y);
    std::uint8_t any = 0;
    for (int x = 0; x < w; ++x) any |= in[x];
    last_clipped[y] = any != 0 ? y : -1;
  }
  const int ring = 2 * r + 1;
  const auto ringRow = [&](int yy) {
    return near_clipped_rows_.data() + static_cast<std::size_t>(yy % ring) * row_bytes;
  };
  int next = 0;  // the first row whose union is not made yet
  for (int y = 0; y < h; ++y) {
    for (; next <= std::min(h - 1, y + r); ++next) {
      if (last_clipped[next] < 0) continue;  // never read
      const std::uint8_t* in = clipped.row(next);
      std::uint8_t* out = ringRow(next);
      std::memset(out, 0, row_bytes);
      for (int d = -r; d <= r; ++d) {
        const int x0 = std::max(0, -d), x1 = std::min(w, w - d);
        for (int x = x0; x < x1; ++x) out[x] |= in[x + d];
      }
    }
    std::uint8_t* out = near_clipped_.row(y);
    std::memset(out, 0, row_bytes);
    bool near = false;
    for (int yy = std::max(0, y - r); yy <= std::min(h - 1, y + r); ++yy) {
      if (last_clipped[yy] < 0) continue;
      near = true;
      const std::uint8_t* in = ringRow(yy);
      for (int x = 0; x < w; ++x) out[x] |= in[x];
    }
    if (!near) continue;  // all zero already
    for (int x = 0; x < w; ++x) out[x] = out[x] != 0 ? 1 : 0;
  }
}

void PixelSelector::dropCornersNearClipped() {
  corners_.erase(
      std::remove_if(corners_.begin(), corners_.end(),
                     [&](const Corner& c) {
                       const int x = std::clamp(static_cast<int>(std::lround(c.u)), 0, width_ - 1);
                       const int y = std::clamp(static_cast<int>(std::lround(c.v)), 0, height_ - 1);
                       return near_clipped_(x, y) != 0;
                     }),
      corners_.end());
}

void PixelSelector::blockAroundCorners() {
  blocked_.fill(0);
  const int r = kCornerExclusionRadius;
  for (const Corner& c : corners_) {
    const int cx = static_cast<int>(std::lround(c.u));
    const int cy = static_cast<int>(std::lround(c.v));
    for (int y = std::max(cy - r, 0); y <= std::min(cy + r, height_ - 1); ++y) {
      for (int x = std::max(cx - r, 0); x <= std::min(cx + r, width_ - 1); ++x)
        blocked_(x, y) = kNearCorner;
    }
  }
}

void PixelSelector::markBelowThreshold(ImageView<const GradientPixel> grad0) {
  // The grid passes look at [kBorder, width - kBorder) x [kBorder, height - kBorder) only. The
  // bounds and table pointers as locals: the byte stores may alias members (char aliasing).
  const int x_end = width_ - kBorder, y_end = height_ - kBorder;
  const int* column_block = thresholds_.blockColumns();
  float* mag_sq = magnitude_sq_.data();
  for (int y = kBorder; y < y_end; ++y) {
    simd::gradientMagnitudeSqRow<simd::Vec4>(grad0.row(y) + kBorder, x_end - kBorder,
                                             mag_sq + kBorder);
    const float* thresholds_sq = thresholds_.rowThresholdsSq(y);
    std::uint8_t* blocked = blocked_.row(y);
    for (int x = kBorder; x < x_end; ++x) {
      const bool weak = mag_sq[x] <= thresholds_sq[column_block[x]];
      blocked[x] = static_cast<std::uint8_t>(blocked[x] | (weak ? kBelowThreshold : 0));
    }
  }
}

int PixelSelector::gridPass(float cell, std::vector<SelectedPixel>& picks) const {
  picks.clear();
  const int x_end = width_ - kBorder;
  const int y_end = height_ - kBorder;
  const int nx = static_cast<int>(std::ceil(static_cast<float>(x_end - kBorder) / cell));
  const int ny = static_cast<int>(std::ceil(static_cast<float>(y_end - kBorder) / cell));
  // Level-0 start of cell i; cells past the last one collapse onto the region's end.
  auto xb = [&](int i) {
    return std::min(kBorder + static_cast<int>(std::floor(static_cast<float>(i) * cell)), x_end);
  };
  auto yb = [&](int j) {
    return std::min(kBorder + static_cast<int>(std::floor(static_cast<float>(j) * cell)), y_end);
  };
  for (int by4 = 0; 4 * by4 < ny; ++by4) {
    for (int bx4 = 0; 4 * bx4 < nx; ++bx4) {
      int found4 = 0;
      for (int by2 = 2 * by4; by2 < 2 * by4 + 2 && 2 * by2 < ny; ++by2) {
        for (int bx2 = 2 * bx4; bx2 < 2 * bx4 + 2 && 2 * bx2 < nx; ++bx2) {
          int found2 = 0;
          for (int cy = 2 * by2; cy < std::min(2 * by2 + 2, ny); ++cy) {
            for (int cx = 2 * bx2; cx < std::min(2 * bx2 + 2, nx); ++cx) {
              found2 +=
                  pickLevel0(xb(cx), xb(cx + 1), yb(cy), yb(cy + 1), cellHash(cx, cy, 0), picks);
            }
          }
          if (found2 == 0 && num_levels_ > 1) {
            found2 += pickCoarse(1, xb(2 * bx2), xb(2 * bx2 + 2), yb(2 * by2), yb(2 * by2 + 2),
                                 cellHash(bx2, by2, 1), picks);
          }
          found4 += found2;
        }
      }
      if (found4 == 0 && num_levels_ > 2) {
        pickCoarse(2, xb(4 * bx4), xb(4 * bx4 + 4), yb(4 * by4), yb(4 * by4 + 4),
                   cellHash(bx4, by4, 2), picks);
      }
    }
  }
  return static_cast<int>(picks.size());
}

bool PixelSelector::pickLevel0(int x0, int x1, int y0, int y1, unsigned cell_hash,
                               std::vector<SelectedPixel>& picks) const {
  const float dx_dir = dir_x_[cell_hash];
  const float dy_dir = dir_y_[cell_hash];
  const ImageView<const GradientPixel>& grad = levels_[0].grad;
  float best_score = -1.f;
  int best_x = -1, best_y = -1;
  float best_mag_sq = 0.f;
  for (int y = y0; y < y1; ++y) {
    const GradientPixel* row = grad.row(y);
    const std::uint8_t* blocked = blocked_.row(y);
    for (int x = x0; x < x1; ++x) {
      if (blocked[x] != 0) continue;  // near a corner or below its threshold
      const float gx = row[x].dx;
      const float gy = row[x].dy;
      const float mag_sq = gx * gx + gy * gy;
      const float along = gx * dx_dir + gy * dy_dir;
      const float score = along * along + kMagnitudeWeight * mag_sq;
      if (score > best_score) {
        best_score = score;
        best_x = x;
        best_y = y;
        best_mag_sq = mag_sq;
      }
    }
  }
  if (best_x < 0) return false;
  picks.push_back(
      {static_cast<float>(best_x), static_cast<float>(best_y), 0, false, std::sqrt(best_mag_sq)});
  return true;
}

bool PixelSelector::pickCoarse(int level, int x0, int x1, int y0, int y1, unsigned cell_hash,
                               std::vector<SelectedPixel>& picks) const {
  const int scale = 1 << level;
  const LevelGrid& lg = levels_[level];
  const ImageView<const GradientPixel>& grad0 = levels_[0].grad;
  const float dx_dir = dir_x_[cell_hash];
  const float dy_dir = dir_y_[cell_hash];
  // Level-l pixels whose scale x scale footprint on level 0 lies inside [x0, x1) x [y0, y1).
  const int lx0 = (x0 + scale - 1) / scale;
  const int lx1 = std::min((x1 - scale) / scale, lg.grad.width - 1);
  const int ly0 = (y0 + scale - 1) / scale;
  const int ly1 = std::min((y1 - scale) / scale, lg.grad.height - 1);
  float best_score = -1.f;
  int best_x = -1, best_y = -1;
  float best_mag_sq = 0.f;
  for (int ly = ly0; ly <= ly1; ++ly) {
    const GradientPixel* row = lg.grad.row(ly);
    for (int lx = lx0; lx <= lx1; ++lx) {
      const float gx = row[lx].dx;
      const float gy = row[lx].dy;
      const float mag_sq = gx * gx + gy * gy;
      if (mag_sq <= lg.threshold_factor_sq * thresholds_.thresholdSq(lx * scale, ly * scale)) {
        continue;
      }
      const float along = gx * dx_dir + gy * dy_dir;
      const float score = along * along + kMagnitudeWeight * mag_sq;
      if (score <= best_score) continue;
      // The strongest free level-0 pixel under this coarse pixel.
      int cx = -1, cy = -1;
      float child_best = -1.f;
      for (int y = ly * scale; y < (ly + 1) * scale; ++y) {
        const GradientPixel* row0 = grad0.row(y);
        for (int x = lx * scale; x < (lx + 1) * scale; ++x) {
          if ((blocked_(x, y) & kNearCorner) != 0) continue;
          const float m = row0[x].dx * row0[x].dx + row0[x].dy * row0[x].dy;
          if (m > child_best) {
            child_best = m;
            cx = x;
            cy = y;
          }
        }
      }
      if (cx < 0) continue;
      best_score = score;
      best_x = cx;
      best_y = cy;
      best_mag_sq = mag_sq;
    }
  }
  if (best_x < 0) return false;
  picks.push_back({static_cast<float>(best_x), static_cast<float>(best_y), level, false,
                   std::sqrt(best_mag_sq)});
  return true;
}

int PixelSelector::detectCorners(const ImagePyramid& pyramid, int max_corners, float min_score,
                                 std::vector<Corner>& out) {
  if (pyramid.levels() < 1 || pyramid.width(0) != width_ || pyramid.height(0) != height_)
    throw InputError("pixel selector: pyramid size differs from the selector's");
  CornerParams params;
  params.max_corners = max_corners;
  params.min_score = min_score;
  params.min_distance = kCornerMinDistance;
  params.border = kCornerBorder;
  return corner_detector_.detect(pyramid.gradients(0), params, out);
}

}  // namespace ldsm
