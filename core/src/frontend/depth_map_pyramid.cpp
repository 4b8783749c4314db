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

}  // namespace

DepthMapPyramid::DepthMapPyramid(int width, int height, int levels, float max_idepth_ratio)
    : max_idepth_ratio_(max_idepth_ratio) {
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
  idepth_sum_.resize(static_cast<std::size_t>(levels));
  weight_sum_.resize(static_cast<std::size_t>(levels));
  points_.resize(static_cast<std::size_t>(levels));
  scratch_idepth_.resize(width, height);
  scratch_weight_.resize(width, height);
  for (int l = 0; l < levels; ++l) {
    idepth_sum_[l].resize(width, height);
    weight_sum_[l].resize(width, height);
    clear(idepth_sum_[l]);
    clear(weight_sum_[l]);
    points_[l].count = 0;
    width /= 2;
    height /= 2;
  }
}

int DepthMapPyramid::build(const DepthPoint* points, std::size_t count,
                           const ImagePyramid& reference) {
  if (reference.levels() < levels() || reference.width(0) != width(0) ||
      reference.height(0) != height(0)) {
    throw InputError("depth map pyramid: reference pyramid is " +
                     sizeString(reference.width(0), reference.height(0)) + " with " +
                     std::to_string(reference.levels()) + " levels, expected " +
                     sizeString(width(0), height(0)) + " with at least " +
                     std::to_string(levels()) + " levels");
  }
  for (int l = 0; l < levels(); ++l) {
    clear(idepth_sum_[l]);
    clear(weight_sum_[l]);
  }
  splat(points, count);
  for (int l = 1; l < levels(); ++l) downsample(l);
  for (int l = 0; l < levels(); ++l) {
    dilate(l, /*diagonal=*/l < 2);
    extract(l, reference);
  }
  return static_cast<int>(count) - rejected_;
}

float DepthMapPyramid::idepthAt(int level, int x, int y) const {
  const float w = weight_sum_[level](x, y);
  return w > 0.f ? idepth_sum_[level](x, y) / w : 0.f;
}

void DepthMapPyramid::splat(const DepthPoint* points, std::size_t count) {
  rejected_ = 0;
  ImageF& sum = idepth_sum_[0];
  ImageF& weight = weight_sum_[0];
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
    sum(x, y) += p.weight * p.idepth;
    weight(x, y) += p.weight;
  }
}

void DepthMapPyramid::downsample(int level) {
  const ImageF& src_sum = idepth_sum_[level - 1];
  const ImageF& src_weight = weight_sum_[level - 1];
  ImageF& sum = idepth_sum_[level];
  ImageF& weight = weight_sum_[level];
  for (int y = 0; y < sum.height(); ++y) {
    const float* s0 = src_sum.row(2 * y);
    const float* s1 = src_sum.row(2 * y + 1);
    const float* w0 = src_weight.row(2 * y);
    const float* w1 = src_weight.row(2 * y + 1);
    float* s = sum.row(y);
    float* w = weight.row(y);
    for (int x = 0; x < sum.width(); ++x) {
      s[x] = s0[2 * x] + s0[2 * x + 1] + s1[2 * x] + s1[2 * x + 1];
      w[x] = w0[2 * x] + w0[2 * x + 1] + w1[2 * x] + w1[2 * x + 1];
    }
  }
}

void DepthMapPyramid::dilate(int level, bool diagonal) {
  ImageF& sum = idepth_sum_[level];
  ImageF& weight = weight_sum_[level];
  const int w = sum.width();
  const int h = sum.height();
  // Read neighbours from a copy so that pixels filled in this pass do not spread further.
  scratch_idepth_.copyFrom(sum.view());
  scratch_weight_.copyFrom(weight.view());
  static constexpr int kDiagonal[4][2] = {{-1, -1}, {1, -1}, {-1, 1}, {1, 1}};
  static constexpr int kCross[4][2] = {{0, -1}, {-1, 0}, {1, 0}, {0, 1}};
  const int(*offsets)[2] = diagonal ? kDiagonal : kCross;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (scratch_weight_(x, y) > 0.f) continue;
      float s = 0.f;
      float ws = 0.f;
      float lo = std::numeric_limits<float>::infinity();
      float hi = 0.f;
      for (int k = 0; k < 4; ++k) {
        const int nx = x + offsets[k][0];
        const int ny = y + offsets[k][1];
        if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
        const float wn = scratch_weight_(nx, ny);
        if (!(wn > 0.f)) continue;
        const float sn = scratch_idepth_(nx, ny);
        s += sn;
        ws += wn;
        lo = std::min(lo, sn / wn);
        hi = std::max(hi, sn / wn);
      }
      // Neighbours on both sides of a depth discontinuity: an average would be a phantom depth.
      if (ws > 0.f && hi <= max_idepth_ratio_ * lo) {
        sum(x, y) = s;
        weight(x, y) = ws;
      }
    }
  }
}

void DepthMapPyramid::extract(int level, const ImagePyramid& reference) {
  const ImageF& sum = idepth_sum_[level];
  const ImageF& weight = weight_sum_[level];
  const ImageView<const GradientPixel> grad = reference.gradients(level);
  LevelPoints& out = points_[level];
  // The point lists grow to the largest count seen (with a quarter of slack) instead of being
  // sized for every pixel: a window's points cover a few percent of a level-0 image, and a
  // 1232x368 pyramid of full-size lists would take 12 MB.
  std::size_t known = 0;
  for (int y = 0; y < weight.height(); ++y) {
    const float* w = weight.row(y);
    for (int x = 0; x < weight.width(); ++x) known += w[x] > 0.f ? 1 : 0;
  }
  if (out.x.size() < known) {
    const std::size_t capacity =
        std::min(known + known / 4, static_cast<std::size_t>(sum.width()) * sum.height());
    for (std::vector<float>* v : {&out.x, &out.y, &out.idepth, &out.intensity, &out.grad_sq})
      v->resize(capacity);
  }
  int n = 0;
  for (int y = 0; y < sum.height(); ++y) {
    const float* s = sum.row(y);
    const float* w = weight.row(y);
    for (int x = 0; x < sum.width(); ++x) {
      if (!(w[x] > 0.f)) continue;
      const GradientPixel& g = grad(x, y);
      out.x[n] = static_cast<float>(x);
      out.y[n] = static_cast<float>(y);
      out.idepth[n] = s[x] / w[x];
      out.intensity[n] = g.intensity;
      out.grad_sq[n] = g.dx * g.dx + g.dy * g.dy;
      ++n;
    }
  }
  out.count = n;
}

}  // namespace ldsm
