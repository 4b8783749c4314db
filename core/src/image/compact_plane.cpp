#include "image/compact_plane.h"

#include <algorithm>
#include <cmath>

#include "image/compact_plane_encode.h"

namespace ldsm {

namespace {

constexpr int kMaxExponent = 14;
constexpr float kMaxStored = 32767.f;

}  // namespace

float CompactPlane::stepFor(float max_abs) {
  int k = kMaxExponent;
  while (k > -126 && max_abs * std::ldexp(1.f, k) > kMaxStored) --k;
  return std::ldexp(1.f, -k);
}

bool CompactPlane::encode(ImageView<const GradientPixel> plane) {
  // The largest magnitude, and whether every value is finite.
  simd::PlaneRange range;
  for (int y = 0; y < plane.height; ++y)
    simd::addToRange<simd::Vec4>(&plane.row(y)->intensity, 3 * plane.width, range);
  if (!range.finite()) {
    clear();
    return false;
  }
  step_ = stepFor(range.max_abs);
  const float inv_step = 1.f / step_;
  width_ = plane.width;
  height_ = plane.height;
  // One pixel past the end: the kernels' 4-lane loads of the last pixel read its first value.
  pixels_.assign(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_) + 1,
                 CompactGradientPixel{0, 0, 0});
  for (int y = 0; y < height_; ++y) {
    const float* in = &plane.row(y)->intensity;
    std::int16_t* out = &pixels_[static_cast<std::size_t>(y) * width_].intensity;
    simd::quantizeRow<simd::Vec4>(in, 3 * width_, inv_step, out);
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
