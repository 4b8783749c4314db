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

bool CompactPlane::encode(ImageView<const float> intensities) {
  // The largest magnitude, and whether every value is finite.
  simd::PlaneRange range;
  for (int y = 0; y < intensities.height; ++y)
    simd::addToRange<simd::Vec4>(intensities.row(y), intensities.width, range);
  if (!range.finite()) {
    clear();
    return false;
  }
  step_ = stepFor(range.max_abs);
  const float inv_step = 1.f / step_;
  width_ = intensities.width;
  height_ = intensities.height;
  pixels_.assign(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_), 0);
  for (int y = 0; y < height_; ++y)
    simd::quantizeRow<simd::Vec4>(intensities.row(y), width_, inv_step,
                                  &pixels_[static_cast<std::size_t>(y) * width_]);
  return true;
}

void CompactPlane::clear() {
  std::vector<std::int16_t>().swap(pixels_);
  width_ = height_ = 0;
  step_ = 0.f;
}

void CompactPlane::copyIntensity(ImageF& out) const {
  const CompactPlaneView v = view();
  out.resize(width_, height_);
  for (int y = 0; y < height_; ++y) {
    float* o = out.row(y);
    for (int x = 0; x < width_; ++x) o[x] = v.intensity(x, y);
  }
}

}  // namespace ldsm
