#include "features/corner_detector.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "features/local_maxima_row.h"
#include "ldsm/error.h"
#include "math/simd/vec4f.h"

namespace ldsm {
namespace {

constexpr int kWindow = 2 * CornerDetector::kWindowRadius + 1;
constexpr float kInvWindowArea = 1.f / static_cast<float>(kWindow * kWindow);

/// Offset in [-0.5, 0.5] of the vertex of the parabola through (-1, a), (0, b), (1, c).
inline float parabolaPeak(float a, float b, float c) {
  const float curvature = a - 2.f * b + c;
  if (!(curvature < 0.f)) return 0.f;
  return std::clamp(0.5f * (a - c) / curvature, -0.5f, 0.5f);
}

}  // namespace

CornerDetector::CornerDetector(int width, int height) : width_(width), height_(height) {
  if (width <= 0 || height <= 0) {
    throw InputError("CornerDetector: image size must be positive (got " + std::to_string(width) +
                     "x" + std::to_string(height) + ")");
  }
  ring_.resize(static_cast<std::size_t>(kRingRows) * 3 * width);
  column_acc_.resize(static_cast<std::size_t>(3) * width);
  score_.resize(width, height);
  score_.fill(0.f);
  // Strict 3x3 local maxima are at most one per 2x2 pixels.
  candidates_.reserve(static_cast<std::size_t>(width / 2 + 1) *
                      static_cast<std::size_t>(height / 2 + 1));
}

int CornerDetector::detect(ImageView<const GradientPixel> gradients, const CornerParams& params,
                           std::vector<Corner>& out) {
  if (gradients.width != width_ || gradients.height != height_) {
    throw InputError("CornerDetector: gradient image is " + std::to_string(gradients.width) + "x" +
                     std::to_string(gradients.height) + ", expected " + std::to_string(width_) +
                     "x" + std::to_string(height_));
  }
  out.clear();
  score_.fill(0.f);
  candidates_.clear();
  scores_border_ = -1;
  if (params.max_corners <= 0) return 0;
  computeScores(gradients, params.border);
  scores_border_ = params.border;
  collectLocalMaxima(params);
  suppressByDistance(params, out);
  return static_cast<int>(out.size());
}

int CornerDetector::reselect(const CornerParams& params, std::vector<Corner>& out) {
  if (scores_border_ < 0) throw InputError("CornerDetector::reselect: no scores computed yet");
  if (params.border != scores_border_) {
    throw InputError("CornerDetector::reselect: border " + std::to_string(params.border) +
                     " differs from the scores' border " + std::to_string(scores_border_));
  }
  out.clear();
  candidates_.clear();
  if (params.max_corners <= 0) return 0;
  collectLocalMaxima(params);
  suppressByDistance(params, out);
  return static_cast<int>(out.size());
}

void CornerDetector::rowSums(ImageView<const GradientPixel> g, int y, int x_lo, int x_hi) {
  const int r = kWindowRadius;
  const GradientPixel* in = g.row(y);
  float* out_xx = ringRow(y, 0);
  float* out_xy = ringRow(y, 1);
  float* out_yy = ringRow(y, 2);
  float xx = 0.f, xy = 0.f, yy = 0.f;
  for (int x = x_lo - r; x <= x_lo + r; ++x) {
    const float p_xx = in[x].dx * in[x].dx, p_xy = in[x].dx * in[x].dy, p_yy = in[x].dy * in[x].dy;
    xx += p_xx;
    xy += p_xy;
    yy += p_yy;
  }
  out_xx[x_lo] = xx;
  out_xy[x_lo] = xy;
  out_yy[x_lo] = yy;
  // Running sums: three independent chains per pixel.
  for (int x = x_lo + 1; x <= x_hi; ++x) {
    const GradientPixel& a = in[x + r];
    const GradientPixel& s = in[x - r - 1];
    const float a_xx = a.dx * a.dx, a_xy = a.dx * a.dy, a_yy = a.dy * a.dy;
    const float s_xx = s.dx * s.dx, s_xy = s.dx * s.dy, s_yy = s.dy * s.dy;
    xx += a_xx - s_xx;
    xy += a_xy - s_xy;
    yy += a_yy - s_yy;
    out_xx[x] = xx;
    out_xy[x] = xy;
    out_yy[x] = yy;
  }
}

void CornerDetector::computeScores(ImageView<const GradientPixel> g, int border) {
  // Scores are needed on [border - 1, size - border] (local maxima and their sub-pixel parabola);
  // the 5x5 window must stay inside the image.
  const int r = kWindowRadius;
  const int x_lo = std::max(border - 1, r);
  const int x_hi = std::min(width_ - border, width_ - 1 - r);
  const int y_lo = std::max(border - 1, r);
  const int y_hi = std::min(height_ - border, height_ - 1 - r);
  if (x_lo > x_hi || y_lo > y_hi) return;

  // Vertical running sums of the horizontal sums (struct of arrays: the loops over x are
  // vector loops), row by row, and the smaller eigenvalue of the mean tensor.
  float* c_xx = column_acc_.data();
  float* c_xy = c_xx + width_;
  float* c_yy = c_xy + width_;
  std::fill(column_acc_.begin(), column_acc_.end(), 0.f);
  for (int y = y_lo - r; y <= y_lo + r; ++y) {
    rowSums(g, y, x_lo, x_hi);
    const float* in_xx = ringRow(y, 0);
    const float* in_xy = ringRow(y, 1);
    const float* in_yy = ringRow(y, 2);
    for (int x = x_lo; x <= x_hi; ++x) {
      c_xx[x] += in_xx[x];
      c_xy[x] += in_xy[x];
      c_yy[x] += in_yy[x];
    }
  }
  using V = simd::Vec4;
  const V inv_area = V::set1(kInvWindowArea);
  const V half = V::set1(0.5f);
  for (int y = y_lo;; ++y) {
    float* s = score_.row(y);
    int x = x_lo;
    for (; x + 4 <= x_hi + 1; x += 4) {
      const V a = V::loadu(c_xx + x) * inv_area;
      const V b = V::loadu(c_xy + x) * inv_area;
      const V c = V::loadu(c_yy + x) * inv_area;
      const V half_diff = half * (a - c);
      const V v = half * (a + c) - squareRoot(half_diff * half_diff + b * b);
      select(v > V::zero(), v, V::zero()).storeu(s + x);
    }
    for (; x <= x_hi; ++x) {
      const float a = c_xx[x] * kInvWindowArea;
      const float b = c_xy[x] * kInvWindowArea;
      const float c = c_yy[x] * kInvWindowArea;
      const float half_diff = 0.5f * (a - c);
      s[x] = std::max(0.5f * (a + c) - std::sqrt(half_diff * half_diff + b * b), 0.f);
    }
    if (y == y_hi) break;
    rowSums(g, y + r + 1, x_lo, x_hi);
    const float* add_xx = ringRow(y + r + 1, 0);
    const float* add_xy = ringRow(y + r + 1, 1);
    const float* add_yy = ringRow(y + r + 1, 2);
    const float* sub_xx = ringRow(y - r, 0);
    const float* sub_xy = ringRow(y - r, 1);
    const float* sub_yy = ringRow(y - r, 2);
    for (int xx = x_lo; xx <= x_hi; ++xx) {
      c_xx[xx] += add_xx[xx] - sub_xx[xx];
      c_xy[xx] += add_xy[xx] - sub_xy[xx];
      c_yy[xx] += add_yy[xx] - sub_yy[xx];
    }
  }
}

void CornerDetector::collectLocalMaxima(const CornerParams& params) {
  const int b = std::max(params.border, 1);
  const float min_score = std::max(params.min_score, 0.f);
  for (int y = b; y <= height_ - 1 - b; ++y) {
    const float* above = score_.row(y - 1);
    const float* s = score_.row(y);
    const float* below = score_.row(y + 1);
    // Strictly above the neighbours that come earlier in raster order, at least equal to the
    // later ones: exactly one pixel of a plateau survives.
    simd::localMaximaRow<simd::Vec4>(above, s, below, b, width_ - b, min_score,
                                     [&](int x, float v) {
                                       candidates_.push_back({v, x, y});
                                     });
  }
  std::sort(candidates_.begin(), candidates_.end(), [](const Candidate& l, const Candidate& r) {
    if (l.score != r.score) return l.score > r.score;
    if (l.y != r.y) return l.y < r.y;
    return l.x < r.x;
  });
}

void CornerDetector::suppressByDistance(const CornerParams& params, std::vector<Corner>& out) {
  // Each kept corner is the maximum of the score map over the (2r + 1)^2 square around it (ties
  // broken by raster order as in collectLocalMaxima), so two kept corners are more than r pixels
  // apart in x or y. Unlike a greedy strongest-first spacing, whether a corner survives depends
  // only on the scores around it, which makes the choice stable under small image changes.
  const int r = std::max(static_cast<int>(std::ceil(params.min_distance)) - 1, 1);
  for (const Candidate& c : candidates_) {
    if (static_cast<int>(out.size()) >= params.max_corners) break;
    const float v = c.score;
    bool is_max = true;
    for (int y = std::max(c.y - r, 0); is_max && y <= std::min(c.y + r, height_ - 1); ++y) {
      const float* s = score_.row(y);
      for (int x = std::max(c.x - r, 0); x <= std::min(c.x + r, width_ - 1); ++x) {
        const bool earlier = y < c.y || (y == c.y && x < c.x);
        if (earlier ? s[x] >= v : s[x] > v) {
          is_max = false;
          break;
        }
      }
    }
    // Integer position for now; refined below.
    if (is_max) out.push_back({static_cast<float>(c.x), static_cast<float>(c.y), c.score});
  }
  for (Corner& c : out) {
    const int x = static_cast<int>(c.u);
    const int y = static_cast<int>(c.v);
    const float* s = score_.row(y);
    c.u += parabolaPeak(s[x - 1], s[x], s[x + 1]);
    c.v += parabolaPeak(score_(x, y - 1), s[x], score_(x, y + 1));
  }
}

}  // namespace ldsm
