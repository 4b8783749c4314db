#include "image/image_pyramid.h"

#include <cstring>
#include <limits>
#include <string>
#include <utility>

#include "image/gradient_row.h"
#include "image/threshold_row.h"
#include "ldsm/error.h"

namespace ldsm {

namespace {

std::string sizeString(int width, int height) {
  return std::to_string(width) + "x" + std::to_string(height);
}

// Row y of level l+1: the mean of the 2x2 blocks of the intensities of level l (packed).
void downsampleRow(const Image<GradientPixel>& src, int y, int w, float* out) {
  const GradientPixel* r0 = src.row(2 * y);
  const GradientPixel* r1 = src.row(2 * y + 1);
  for (int x = 0; x < w; ++x) {
    out[x] = 0.25f * ((r0[2 * x].intensity + r0[2 * x + 1].intensity) +
                      (r1[2 * x].intensity + r1[2 * x + 1].intensity));
  }
}

}  // namespace

int ImagePyramid::maxLevels(int width, int height) {
  int levels = 0;
  while (width >= 1 && height >= 1 && levels < kMaxLevels) {
    ++levels;
    width /= 2;
    height /= 2;
  }
  return levels;
}

ImagePyramid::ImagePyramid(int width, int height, int levels, bool with_grad_mag_sq) {
  if (width <= 0 || height <= 0) {
    throw InputError("image pyramid: image size must be positive (got " +
                     sizeString(width, height) + ")");
  }
  const int max_levels = maxLevels(width, height);
  if (levels < 1 || levels > max_levels) {
    throw ConfigError("image pyramid: levels must be in [1, " + std::to_string(max_levels) +
                      "] for a " + sizeString(width, height) + " image (got " +
                      std::to_string(levels) + ")");
  }
  with_grad_mag_sq_ = with_grad_mag_sq;
  for (int l = 0; l < levels; ++l) {
    sizes_.emplace_back(width, height);
    width /= 2;
    height /= 2;
  }
  if (levels > 1) rows_.resize(3 * static_cast<std::size_t>(sizes_[1].first));
  allocatePlanes();
}

void ImagePyramid::allocatePlanes() {
  const std::size_t n = sizes_.size();
  clipped_.resize(sizes_[0].first, sizes_[0].second);
  gradients_.resize(n);
  if (with_grad_mag_sq_) grad_mag_sq_.resize(n);
  for (std::size_t l = 0; l < n; ++l) {
    const auto [w, h] = sizes_[l];
    gradients_[l].resize(w, h);
    if (with_grad_mag_sq_) grad_mag_sq_[l].resize(w, h);
  }
}

void ImagePyramid::compact(bool level0_16bit) {
  if (compacted_) return;
  // Assigning an empty image frees the plane (Image's move assignment swaps).
  clipped_ = Image<std::uint8_t>();
  for (std::size_t l = 1; l < gradients_.size(); ++l) gradients_[l] = Image<GradientPixel>();
  for (ImageF& plane : grad_mag_sq_) plane = ImageF();
  copyIntensity(0, intensity0_);
  gradients_[0] = Image<GradientPixel>();
  if (level0_16bit && compact0_.encode(intensity0_.view())) intensity0_ = ImageF();
  compacted_ = true;
}

void ImagePyramid::expand() {
  if (!compacted_) return;
  allocatePlanes();
  compact0_.clear();
  intensity0_ = ImageF();
  intensity0_taken_ = false;
  compacted_ = false;
}

std::size_t ImagePyramid::bytes() const {
  std::size_t n = clipped_.capacity() * sizeof(std::uint8_t);
  for (const Image<GradientPixel>& plane : gradients_)
    n += plane.capacity() * sizeof(GradientPixel);
  for (const ImageF& plane : grad_mag_sq_) n += plane.capacity() * sizeof(float);
  return n + compact0_.bytes() + intensity0_.capacity() * sizeof(float);
}

void ImagePyramid::takeIntensity0(ImageF& out) {
  if (!compacted_ || !compact0_.empty() || intensity0_taken_) {
    copyIntensity(0, out);
    return;
  }
  out = std::move(intensity0_);
  intensity0_ = ImageF();
  intensity0_taken_ = true;
}

void ImagePyramid::copyIntensity(int level, ImageF& out) const {
  if (intensity0_taken_ && level == 0)
    throw std::logic_error("image pyramid: level 0 was handed on (takeIntensity0)");
  if (level == 0 && !compact0_.empty()) {
    compact0_.copyIntensity(out);
    return;
  }
  if (level == 0 && compacted_) {
    const ImageView<const float> in = intensity0_.view();
    out.resize(in.width, in.height);
    for (int y = 0; y < in.height; ++y)
      std::memcpy(out.row(y), in.row(y), in.width * sizeof(float));
    return;
  }
  const ImageView<const GradientPixel> g = gradients(level);
  out.resize(g.width, g.height);
  for (int y = 0; y < g.height; ++y) {
    const GradientPixel* in = g.row(y);
    float* o = out.row(y);
    for (int x = 0; x < g.width; ++x) o[x] = in[x].intensity;
  }
}

namespace {

// The rows of a whole image, as build(ImageRows&) asks for them.
class ViewRows final : public ImageRows {
 public:
  explicit ViewRows(ImageView<const float> image) : image_(image) {}
  const float* row(int y) override { return image_.row(y); }

 private:
  ImageView<const float> image_;
};

}  // namespace

void ImagePyramid::build(ImageView<const float> image) {
  if (image.empty() || image.width != width(0) || image.height != height(0) ||
      image.stride < image.width) {
    expand();
    throw InputError("image pyramid: input image is " + sizeString(image.width, image.height) +
                     " with stride " + std::to_string(image.stride) + ", expected " +
                     sizeString(width(0), height(0)));
  }
  ViewRows rows(image);
  build(rows);
}

void ImagePyramid::build(ImageRows& rows) {
  build(rows, std::numeric_limits<float>::infinity());
}

void ImagePyramid::build(ImageRows& rows, float clipped_level) {
  expand();
  const int w0 = width(0);
  const int h0 = height(0);
  // Row y needs rows y - 1 and y + 1 as well: each is asked for once, in order.
  const float* in[3] = {rows.row(0), nullptr, nullptr};
  if (h0 > 1) in[1] = rows.row(1);
  for (int y = 0; y < h0; ++y) {
    if (y + 1 < h0 && y >= 1) in[(y + 1) % 3] = rows.row(y + 1);
    const bool inner = y > 0 && y < h0 - 1;
    simd::gradientRow<simd::Vec4>(inner ? in[(y + 2) % 3] : nullptr, in[y % 3],
                                  inner ? in[(y + 1) % 3] : nullptr, w0, gradients_[0].row(y));
    if (clipped_level < std::numeric_limits<float>::infinity())
      simd::markAtLeastRow<simd::Vec4>(in[y % 3], w0, clipped_level, clipped_.row(y));
    else
      std::memset(clipped_.row(y), 0, static_cast<std::size_t>(w0));
  }
  computeGradMagSq(0);
  // Coarser levels: each row's intensities are made once into a ring of three rows (the row, the
  // one above and the one below), from the packed plane of the level before.
  for (int l = 1; l < levels(); ++l) {
    const int w = width(l);
    const int h = height(l);
    float* ring[3] = {rows_.data(), rows_.data() + w, rows_.data() + 2 * w};
    downsampleRow(gradients_[l - 1], 0, w, ring[0]);
    if (h > 1) downsampleRow(gradients_[l - 1], 1, w, ring[1]);
    for (int y = 0; y < h; ++y) {
      if (y + 1 < h && y >= 1) downsampleRow(gradients_[l - 1], y + 1, w, ring[(y + 1) % 3]);
      const bool inner = y > 0 && y < h - 1;
      simd::gradientRow<simd::Vec4>(inner ? ring[(y + 2) % 3] : nullptr, ring[y % 3],
                                    inner ? ring[(y + 1) % 3] : nullptr, w, gradients_[l].row(y));
    }
    computeGradMagSq(l);
  }
}

void ImagePyramid::markClipped(ImageView<const float> raw, float level) {
  requireFull("clipping mask", 0);
  if (raw.empty() || raw.width != width(0) || raw.height != height(0) || raw.stride < raw.width) {
    throw InputError("image pyramid: clipping source is " + sizeString(raw.width, raw.height) +
                     ", expected " + sizeString(width(0), height(0)));
  }
  for (int y = 0; y < raw.height; ++y) {
    simd::markAtLeastRow<simd::Vec4>(raw.row(y), raw.width, level, clipped_.row(y));
  }
}

void ImagePyramid::markClipped(ImageRows& raw, float level) {
  requireFull("clipping mask", 0);
  const int w = width(0), h = height(0);
  for (int y = 0; y < h; ++y)
    simd::markAtLeastRow<simd::Vec4>(raw.row(y), w, level, clipped_.row(y));
}

void ImagePyramid::markClippedFromIntensity(float level) {
  requireFull("clipping mask", 0);
  for (int y = 0; y < height(0); ++y) {
    const GradientPixel* in = gradients_[0].row(y);
    std::uint8_t* out = clipped_.row(y);
    for (int x = 0; x < width(0); ++x) out[x] = in[x].intensity >= level ? 1 : 0;
  }
}

void ImagePyramid::computeGradMagSq(int level) {
  if (grad_mag_sq_.empty()) return;
  const Image<GradientPixel>& grad = gradients_[level];
  ImageF& mag = grad_mag_sq_[level];
  for (int y = 0; y < grad.height(); ++y) {
    const GradientPixel* g = grad.row(y);
    float* out = mag.row(y);
    for (int x = 0; x < grad.width(); ++x) out[x] = g[x].dx * g[x].dx + g[x].dy * g[x].dy;
  }
}

}  // namespace ldsm
