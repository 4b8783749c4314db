#include "frontend/depth_map_pyramid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "ldsm/error.h"

namespace ldsm {

namespace {

std::string sizeString(int width, int height) {
  return std::to_string(width) + "x" + std::to_string(height);
}

void checkSizes(int width, int height, int levels) {
  if (width <= 0 || height <= 0) {
    throw InputError("depth map pyramid: image size must be positive (got " +
                     sizeString(width, height) + ")");
  }
  const int max_levels = ImagePyramid::maxLevels(width, height);
  if (levels < 1 || levels > max_levels) {
    throw ConfigError("depth map pyramid: levels must be in [1, " + std::to_string(max_levels) +
                      "] for a " + sizeString(width, height) + " image (got " +
                      std::to_string(levels) + ")");
  }
}

template <typename Src>
void downsampleLevel(const Src& src, int src_width, const std::vector<int>& src_known,
                     DensePixelSums& dst, int w, int h, std::vector<int>& known) {
  // Every parent of a known child, once; its sums gathered from its 2x2 children in a fixed
  // order (the value does not depend on which child found it; a child without a cell adds 0).
  for (const int i : src_known) {
    const int x = (i % src_width) / 2;
    const int y = (i / src_width) / 2;
    const int parent = y * w + x;
    if (x >= w || y >= h || dst.weight(parent) > 0.f) continue;
    const int c00 = 2 * y * src_width + 2 * x;
    const int c10 = c00 + src_width;
    const float sum = src.sum(c00) + src.sum(c00 + 1) + src.sum(c10) + src.sum(c10 + 1);
    const float weight =
        src.weight(c00) + src.weight(c00 + 1) + src.weight(c10) + src.weight(c10 + 1);
    DensePixelSums::Cell& cell = dst.insert(parent);
    cell.sum = sum;
    cell.weight = weight;
    known.push_back(parent);
  }
}

template <typename Sums>
void dilateLevel(Sums& sums, int w, int h, bool diagonal, float max_idepth_ratio,
                 std::vector<int>& known, std::vector<DepthMapCanvas::Fill>& fills) {
  static constexpr int kDiagonal[4][2] = {{-1, -1}, {1, -1}, {-1, 1}, {1, 1}};
  static constexpr int kCross[4][2] = {{0, -1}, {-1, 0}, {1, 0}, {0, 1}};
  const int(*offsets)[2] = diagonal ? kDiagonal : kCross;
  // The empty pixels next to a known one (the offsets are symmetric), each once: marked with a
  // negative weight, which reads as unknown below.
  constexpr float kCandidate = -1.f;
  fills.clear();
  for (const int i : known) {
    const int x = i % w, y = i / w;
    for (int k = 0; k < 4; ++k) {
      const int nx = x + offsets[k][0];
      const int ny = y + offsets[k][1];
      if (nx < 0 || ny < 0 || nx >= w || ny >= h || sums.weight(ny * w + nx) != 0.f) continue;
      sums.insert(ny * w + nx).weight = kCandidate;
      fills.push_back({ny * w + nx, 0.f, 0.f});
    }
  }
  // Each from the known neighbours before this pass, so that filled pixels do not spread further.
  for (DepthMapCanvas::Fill& f : fills) {
    const int x = f.index % w, y = f.index / w;
    float s = 0.f;
    float ws = 0.f;
    float lo = std::numeric_limits<float>::infinity();
    float hi = 0.f;
    for (int k = 0; k < 4; ++k) {
      const int nx = x + offsets[k][0];
      const int ny = y + offsets[k][1];
      if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
      const auto* n = sums.find(ny * w + nx);
      if (n == nullptr || !(n->weight > 0.f)) continue;
      const float wn = n->weight;
      const float sn = n->sum;
      s += sn;
      ws += wn;
      lo = std::min(lo, sn / wn);
      hi = std::max(hi, sn / wn);
    }
    // Neighbours on both sides of a depth discontinuity: an average would be a phantom depth.
    const bool fill = ws > 0.f && hi <= max_idepth_ratio * lo;
    f.sum = fill ? s : 0.f;
    f.weight = fill ? ws : 0.f;
  }
  for (const DepthMapCanvas::Fill& f : fills) {
    auto& cell = sums.insert(f.index);  // there since the first pass
    cell.sum = f.sum;
    cell.weight = f.weight;
    if (f.weight > 0.f) known.push_back(f.index);
  }
}

template <typename Sums>
void extractLevel(const Sums& sums, int w, int h, ImageView<const GradientPixel> grad,
                  std::vector<int>& known, LevelPoints& out) {
  // Row by row, as a scan of the level would list them.
  std::sort(known.begin(), known.end());
  // The point lists grow to the largest count seen (with a quarter of slack) instead of being
  // sized for every pixel: a window's points cover a few percent of a level-0 image, and a
  // 1232x368 pyramid of full-size lists would take 12 MB.
  if (out.x.size() < known.size()) {
    const std::size_t capacity = std::min(
        known.size() + known.size() / 4, static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
    for (std::vector<float>* v : {&out.x, &out.y, &out.idepth, &out.intensity, &out.grad_sq})
      v->resize(capacity);
  }
  int n = 0;
  for (const int i : known) {
    const int x = i % w, y = i / w;
    const GradientPixel& g = grad(x, y);
    const auto cell = sums.get(i);
    out.x[n] = static_cast<float>(x);
    out.y[n] = static_cast<float>(y);
    out.idepth[n] = cell.sum / cell.weight;
    out.intensity[n] = g.intensity;
    out.grad_sq[n] = g.dx * g.dx + g.dy * g.dy;
    ++n;
  }
  out.count = n;
}

}  // namespace

DepthMapCanvas::DepthMapCanvas(int width, int height, int levels) {
  checkSizes(width, height, levels);
  for (int l = 0; l < levels; ++l) {
    sizes_.emplace_back(width, height);
    width /= 2;
    height /= 2;
  }
  level0_ = PixelSums(
      1024, static_cast<std::size_t>(sizes_[0].first) * static_cast<std::size_t>(sizes_[0].second));
  for (int l = 1; l < levels; ++l)
    coarse_.emplace_back(static_cast<std::size_t>(sizes_[l].first) *
                         static_cast<std::size_t>(sizes_[l].second));
  known_.resize(static_cast<std::size_t>(levels));
}

float DepthMapCanvas::idepthAt(int level, int x, int y) const {
  const int pixel = y * width(level) + x;
  const float w = level == 0 ? level0_.weight(pixel) : coarse_[level - 1].weight(pixel);
  const float s = level == 0 ? level0_.sum(pixel) : coarse_[level - 1].sum(pixel);
  return w > 0.f ? s / w : 0.f;
}

std::size_t DepthMapCanvas::bytes() const {
  std::size_t b = fills_.capacity() * sizeof(Fill);
  b += level0_.bytes();
  for (const DensePixelSums& level : coarse_) b += level.bytes();
  for (const std::vector<int>& known : known_) b += known.capacity() * sizeof(int);
  return b;
}

DepthMapPyramid::DepthMapPyramid(int width, int height, int levels, float max_idepth_ratio)
    : width_(width), height_(height), max_idepth_ratio_(max_idepth_ratio) {
  checkSizes(width, height, levels);
  points_.resize(static_cast<std::size_t>(levels));
}

int DepthMapPyramid::build(const DepthPoint* points, std::size_t count,
                           const ImagePyramid& reference) {
  if (!own_canvas_) own_canvas_ = std::make_unique<DepthMapCanvas>(width_, height_, levels());
  return build(points, count, reference, *own_canvas_);
}

int DepthMapPyramid::build(const DepthPoint* points, std::size_t count,
                           const ImagePyramid& reference, DepthMapCanvas& canvas) {
  if (reference.levels() < levels() || reference.width(0) != width(0) ||
      reference.height(0) != height(0)) {
    throw InputError("depth map pyramid: reference pyramid is " +
                     sizeString(reference.width(0), reference.height(0)) + " with " +
                     std::to_string(reference.levels()) + " levels, expected " +
                     sizeString(width(0), height(0)) + " with at least " +
                     std::to_string(levels()) + " levels");
  }
  if (canvas.levels() < levels() || canvas.width(0) != width(0) || canvas.height(0) != height(0)) {
    throw InputError(
        "depth map pyramid: canvas is " + sizeString(canvas.width(0), canvas.height(0)) + " with " +
        std::to_string(canvas.levels()) + " levels, expected " + sizeString(width(0), height(0)) +
        " with at least " + std::to_string(levels()) + " levels");
  }
  canvas.level0_.clear();
  for (int l = 0; l < canvas.levels(); ++l) {
    if (l > 0) canvas.coarse_[l - 1].clear(canvas.known_[l]);
    canvas.known_[l].clear();
  }
  last_canvas_ = &canvas;
  splat(points, count, canvas);
  for (int l = 1; l < levels(); ++l) downsample(l, canvas);
  for (int l = 0; l < levels(); ++l) {
    dilate(l, /*diagonal=*/l < 2, canvas);
    extract(l, reference, canvas);
  }
  return static_cast<int>(count) - rejected_;
}

float DepthMapPyramid::idepthAt(int level, int x, int y) const {
  return last_canvas_ != nullptr ? last_canvas_->idepthAt(level, x, y) : 0.f;
}

std::size_t DepthMapPyramid::bytes() const {
  std::size_t b = own_canvas_ ? own_canvas_->bytes() : 0;
  for (const LevelPoints& p : points_) b += 5 * sizeof(float) * p.x.capacity();
  return b;
}

void DepthMapPyramid::splat(const DepthPoint* points, std::size_t count, DepthMapCanvas& c) {
  rejected_ = 0;
  PixelSums& sums = c.level0_;
  std::vector<int>& known = c.known_[0];
  const int w = c.width(0), h = c.height(0);
  for (std::size_t i = 0; i < count; ++i) {
    const DepthPoint& p = points[i];
    const bool valid = std::isfinite(p.u) && std::isfinite(p.v) && std::isfinite(p.idepth) &&
                       std::isfinite(p.weight) && p.idepth > 0.f && p.weight > 0.f;
    const float fx = valid ? std::floor(p.u + 0.5f) : -1.f;
    const float fy = valid ? std::floor(p.v + 0.5f) : -1.f;
    if (!(fx >= 0.f && fy >= 0.f && fx < static_cast<float>(w) && fy < static_cast<float>(h))) {
      ++rejected_;
      continue;
    }
    const int pixel = static_cast<int>(fy) * w + static_cast<int>(fx);
    PixelSums::Cell* cell = sums.find(pixel);
    if (cell == nullptr) {  // level 0 has only cells of positive weight before dilation
      cell = &sums.insert(pixel);
      known.push_back(pixel);
      cell->from_map = p.from_map;
    } else if (p.from_map != (cell->from_map != 0)) {
      // A map keyframe's point and the window's at one pixel, on both sides of a depth
      // discontinuity: only the nearer surface is seen there.
      const float seen = cell->sum / cell->weight;
      if (p.idepth * max_idepth_ratio_ < seen) continue;
      if (p.idepth > max_idepth_ratio_ * seen) {
        cell->sum = p.weight * p.idepth;
        cell->weight = p.weight;
        cell->from_map = p.from_map;
        continue;
      }
    }
    cell->sum += p.weight * p.idepth;
    cell->weight += p.weight;
  }
}

void DepthMapPyramid::downsample(int level, DepthMapCanvas& c) const {
  DensePixelSums& dst = c.coarse_[level - 1];
  if (level == 1)
    downsampleLevel(c.level0_, c.width(0), c.known_[0], dst, c.width(1), c.height(1), c.known_[1]);
  else
    downsampleLevel(c.coarse_[level - 2], c.width(level - 1), c.known_[level - 1], dst,
                    c.width(level), c.height(level), c.known_[level]);
}

void DepthMapPyramid::dilate(int level, bool diagonal, DepthMapCanvas& c) const {
  if (level == 0)
    dilateLevel(c.level0_, c.width(0), c.height(0), diagonal, max_idepth_ratio_, c.known_[0],
                c.fills_);
  else
    dilateLevel(c.coarse_[level - 1], c.width(level), c.height(level), diagonal, max_idepth_ratio_,
                c.known_[level], c.fills_);
}

void DepthMapPyramid::extract(int level, const ImagePyramid& reference, DepthMapCanvas& c) {
  const ImageView<const GradientPixel> grad = reference.gradients(level);
  if (level == 0)
    extractLevel(c.level0_, c.width(0), c.height(0), grad, c.known_[0], points_[0]);
  else
    extractLevel(c.coarse_[level - 1], c.width(level), c.height(level), grad, c.known_[level],
                 points_[level]);
}

}  // namespace ldsm
