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

void clear(ImageF& image) {
  image.fill(0.f);
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

}  // namespace

DepthMapCanvas::DepthMapCanvas(int width, int height, int levels) {
  checkSizes(width, height, levels);
  from_map_.assign(static_cast<std::size_t>(width) * height, 0);
  idepth_sum_.resize(static_cast<std::size_t>(levels));
  weight_sum_.resize(static_cast<std::size_t>(levels));
  known_.resize(static_cast<std::size_t>(levels));
  for (int l = 0; l < levels; ++l) {
    idepth_sum_[l].resize(width, height);
    weight_sum_[l].resize(width, height);
    clear(idepth_sum_[l]);
    clear(weight_sum_[l]);
    width /= 2;
    height /= 2;
  }
}

float DepthMapCanvas::idepthAt(int level, int x, int y) const {
  const float w = weight_sum_[level](x, y);
  return w > 0.f ? idepth_sum_[level](x, y) / w : 0.f;
}

std::size_t DepthMapCanvas::bytes() const {
  std::size_t b = from_map_.capacity() + fills_.capacity() * sizeof(Fill);
  for (int l = 0; l < levels(); ++l) {
    b += 2 * sizeof(float) * static_cast<std::size_t>(width(l)) * height(l);
    b += known_[l].capacity() * sizeof(int);
  }
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
  // Only the pixels the canvas's last build filled are non-zero (on every level it has).
  for (const int i : canvas.known_[0]) canvas.from_map_[i] = 0;
  for (int l = 0; l < canvas.levels(); ++l) {
    float* sum = canvas.idepth_sum_[l].data();
    float* weight = canvas.weight_sum_[l].data();
    for (const int i : canvas.known_[l]) sum[i] = weight[i] = 0.f;
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
  ImageF& sum = c.idepth_sum_[0];
  ImageF& weight = c.weight_sum_[0];
  std::vector<int>& known = c.known_[0];
  std::vector<unsigned char>& from_map = c.from_map_;
  for (std::size_t i = 0; i < count; ++i) {
    const DepthPoint& p = points[i];
    const bool valid = std::isfinite(p.u) && std::isfinite(p.v) && std::isfinite(p.idepth) &&
                       std::isfinite(p.weight) && p.idepth > 0.f && p.weight > 0.f;
    const float fx = valid ? std::floor(p.u + 0.5f) : -1.f;
    const float fy = valid ? std::floor(p.v + 0.5f) : -1.f;
    if (!(fx >= 0.f && fy >= 0.f && fx < static_cast<float>(sum.width()) &&
          fy < static_cast<float>(sum.height()))) {
      ++rejected_;
      continue;
    }
    const int x = static_cast<int>(fx);
    const int y = static_cast<int>(fy);
    const int pixel = y * sum.width() + x;
    if (!(weight(x, y) > 0.f)) {
      known.push_back(pixel);
      from_map[pixel] = p.from_map;
    } else if (p.from_map != (from_map[pixel] != 0)) {
      // A map keyframe's point and the window's at one pixel, on both sides of a depth
      // discontinuity: only the nearer surface is seen there.
      const float seen = sum(x, y) / weight(x, y);
      if (p.idepth * max_idepth_ratio_ < seen) continue;
      if (p.idepth > max_idepth_ratio_ * seen) {
        sum(x, y) = p.weight * p.idepth;
        weight(x, y) = p.weight;
        from_map[pixel] = p.from_map;
        continue;
      }
    }
    sum(x, y) += p.weight * p.idepth;
    weight(x, y) += p.weight;
  }
}

void DepthMapPyramid::downsample(int level, DepthMapCanvas& c) const {
  const ImageF& src_sum = c.idepth_sum_[level - 1];
  const ImageF& src_weight = c.weight_sum_[level - 1];
  ImageF& sum = c.idepth_sum_[level];
  ImageF& weight = c.weight_sum_[level];
  const int src_width = src_sum.width();
  std::vector<int>& known = c.known_[level];
  // Every parent of a known child, once; its sums gathered from its 2x2 children in a fixed
  // order (the value does not depend on which child found it).
  for (const int i : c.known_[level - 1]) {
    const int x = (i % src_width) / 2;
    const int y = (i / src_width) / 2;
    if (x >= sum.width() || y >= sum.height() || weight(x, y) > 0.f) continue;
    const float* s0 = src_sum.row(2 * y);
    const float* s1 = src_sum.row(2 * y + 1);
    const float* w0 = src_weight.row(2 * y);
    const float* w1 = src_weight.row(2 * y + 1);
    sum(x, y) = s0[2 * x] + s0[2 * x + 1] + s1[2 * x] + s1[2 * x + 1];
    weight(x, y) = w0[2 * x] + w0[2 * x + 1] + w1[2 * x] + w1[2 * x + 1];
    known.push_back(y * sum.width() + x);
  }
}

void DepthMapPyramid::dilate(int level, bool diagonal, DepthMapCanvas& c) const {
  ImageF& sum = c.idepth_sum_[level];
  ImageF& weight = c.weight_sum_[level];
  std::vector<DepthMapCanvas::Fill>& fills = c.fills_;
  const int w = sum.width();
  const int h = sum.height();
  static constexpr int kDiagonal[4][2] = {{-1, -1}, {1, -1}, {-1, 1}, {1, 1}};
  static constexpr int kCross[4][2] = {{0, -1}, {-1, 0}, {1, 0}, {0, 1}};
  const int(*offsets)[2] = diagonal ? kDiagonal : kCross;
  // The empty pixels next to a known one (the offsets are symmetric), each once: marked with a
  // negative weight, which reads as unknown below.
  constexpr float kCandidate = -1.f;
  fills.clear();
  for (const int i : c.known_[level]) {
    const int x = i % w, y = i / w;
    for (int k = 0; k < 4; ++k) {
      const int nx = x + offsets[k][0];
      const int ny = y + offsets[k][1];
      if (nx < 0 || ny < 0 || nx >= w || ny >= h || weight(nx, ny) != 0.f) continue;
      weight(nx, ny) = kCandidate;
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
      const float wn = weight(nx, ny);
      if (!(wn > 0.f)) continue;
      const float sn = sum(nx, ny);
      s += sn;
      ws += wn;
      lo = std::min(lo, sn / wn);
      hi = std::max(hi, sn / wn);
    }
    // Neighbours on both sides of a depth discontinuity: an average would be a phantom depth.
    const bool fill = ws > 0.f && hi <= max_idepth_ratio_ * lo;
    f.sum = fill ? s : 0.f;
    f.weight = fill ? ws : 0.f;
  }
  std::vector<int>& known = c.known_[level];
  for (const DepthMapCanvas::Fill& f : fills) {
    sum.data()[f.index] = f.sum;
    weight.data()[f.index] = f.weight;
    if (f.weight > 0.f) known.push_back(f.index);
  }
}

void DepthMapPyramid::extract(int level, const ImagePyramid& reference, DepthMapCanvas& c) {
  const ImageF& sum = c.idepth_sum_[level];
  const ImageF& weight = c.weight_sum_[level];
  const ImageView<const GradientPixel> grad = reference.gradients(level);
  LevelPoints& out = points_[level];
  // Row by row, as a scan of the level would list them.
  std::vector<int>& known = c.known_[level];
  std::sort(known.begin(), known.end());
  // The point lists grow to the largest count seen (with a quarter of slack) instead of being
  // sized for every pixel: a window's points cover a few percent of a level-0 image, and a
  // 1232x368 pyramid of full-size lists would take 12 MB.
  if (out.x.size() < known.size()) {
    const std::size_t capacity = std::min(known.size() + known.size() / 4,
                                          static_cast<std::size_t>(sum.width()) * sum.height());
    for (std::vector<float>* v : {&out.x, &out.y, &out.idepth, &out.intensity, &out.grad_sq})
      v->resize(capacity);
  }
  const int w = sum.width();
  int n = 0;
  for (const int i : known) {
    const int x = i % w, y = i / w;
    const GradientPixel& g = grad(x, y);
    out.x[n] = static_cast<float>(x);
    out.y[n] = static_cast<float>(y);
    out.idepth[n] = sum.data()[i] / weight.data()[i];
    out.intensity[n] = g.intensity;
    out.grad_sq[n] = g.dx * g.dx + g.dy * g.dy;
    ++n;
  }
  out.count = n;
}

}  // namespace ldsm
