#include "image/compact_plane.h"

#include <algorithm>
#include <cmath>

namespace ldsm {

namespace {

constexpr int kMaxExponent = 14;
constexpr float kMaxStored = 32767.f;
/// 1.5 * 2^23: adding and subtracting it rounds a float of magnitude below 2^22 to the nearest
/// integer (ties to even), without a branch.
constexpr float kRoundingBias = 12582912.f;

/// round(v / step) for |v / step| <= 32767 (v / step is exact: a power of two apart).
std::int16_t quantize(float v, float inv_step) {
  const float s = v * inv_step;
  return static_cast<std::int16_t>(static_cast<int>((s + kRoundingBias) - kRoundingBias));
}

}  // namespace

float CompactPlane::stepFor(float max_abs) {
  int k = kMaxExponent;
  while (k > -126 && max_abs * std::ldexp(1.f, k) > kMaxStored) --k;
  return std::ldexp(1.f, -k);
}

bool CompactPlane::encode(ImageView<const GradientPixel> plane) {
  // The largest magnitude; `zero` stays 0 unless a value is NaN or infinite (v * 0 is NaN then).
  float max_abs = 0.f;
  float zero = 0.f;
  for (int y = 0; y < plane.height; ++y) {
    const float* v = &plane.row(y)->intensity;
    for (int i = 0; i < 3 * plane.width; ++i) {
      const float a = std::fabs(v[i]);
      max_abs = a > max_abs ? a : max_abs;
      zero += v[i] * 0.f;
    }
  }
  if (!(zero == 0.f)) {
    clear();
    return false;
  }
  step_ = stepFor(max_abs);
  const float inv_step = 1.f / step_;
  width_ = plane.width;
  height_ = plane.height;
  // One pixel past the end: the kernels' 4-lane loads of the last pixel read its first value.
  pixels_.assign(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_) + 1,
                 CompactGradientPixel{0, 0, 0});
  for (int y = 0; y < height_; ++y) {
    const float* in = &plane.row(y)->intensity;
    std::int16_t* out = &pixels_[static_cast<std::size_t>(y) * width_].intensity;
    for (int i = 0; i < 3 * width_; ++i) out[i] = quantize(in[i], inv_step);
  }
  return true;
}

void CompactPlane::clear() {
  std::vector<CompactGradientPixel>().swap(pixels_);
  width_ = height_ = 0;
  step_ = 0.f;
}

void CompactPlane::copyIntensity(ImageF& out) const {
  const CompactPlaneView v = view();
  out.resize(width_, height_);
  for (int y = 0; y < height_; ++y) {
    float* o = out.row(y);
    const CompactGradientPixel* in = v.pixels.row(y);
    for (int x = 0; x < width_; ++x) o[x] = step_ * static_cast<float>(in[x].intensity);
  }
}

}  // namespace ldsm
