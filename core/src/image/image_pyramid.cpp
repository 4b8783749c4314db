#include "image/image_pyramid.h"

#include <cstring>
#include <string>

#include "ldsm/error.h"

namespace ldsm {

namespace {

std::string sizeString(int width, int height) {
  return std::to_string(width) + "x" + std::to_string(height);
}

// dst(x, y) = mean of the 2x2 block of src at (2x, 2y); dst is floor(src / 2) in size.
void downsample2x2(ImageView<const float> src, ImageView<float> dst) {
  for (int y = 0; y < dst.height; ++y) {
    const float* r0 = src.row(2 * y);
    const float* r1 = src.row(2 * y + 1);
    float* out = dst.row(y);
    for (int x = 0; x < dst.width; ++x) {
      out[x] = 0.25f * ((r0[2 * x] + r0[2 * x + 1]) + (r1[2 * x] + r1[2 * x + 1]));
    }
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
  allocatePlanes();
}

void ImagePyramid::allocatePlanes() {
  const std::size_t n = sizes_.size();
  clipped_.resize(sizes_[0].first, sizes_[0].second);
  intensity_.resize(n);
  gradients_.resize(n);
  if (with_grad_mag_sq_) grad_mag_sq_.resize(n);
  for (std::size_t l = 0; l < n; ++l) {
    const auto [w, h] = sizes_[l];
    intensity_[l].resize(w, h);
    gradients_[l].resize(w, h);
    if (with_grad_mag_sq_) grad_mag_sq_[l].resize(w, h);
  }
}

void ImagePyramid::compact() {
  if (compacted_) return;
  // Assigning an empty image frees the plane (Image's move assignment swaps).
  clipped_ = Image<std::uint8_t>();
  for (ImageF& plane : intensity_) plane = ImageF();
  for (std::size_t l = 1; l < gradients_.size(); ++l) gradients_[l] = Image<GradientPixel>();
  for (ImageF& plane : grad_mag_sq_) plane = ImageF();
  compacted_ = true;
}

void ImagePyramid::expand() {
  if (!compacted_) return;
  allocatePlanes();
  compacted_ = false;
}

std::size_t ImagePyramid::bytes() const {
  std::size_t n = clipped_.capacity() * sizeof(std::uint8_t);
  for (const ImageF& plane : intensity_) n += plane.capacity() * sizeof(float);
  for (const Image<GradientPixel>& plane : gradients_)
    n += plane.capacity() * sizeof(GradientPixel);
  for (const ImageF& plane : grad_mag_sq_) n += plane.capacity() * sizeof(float);
  return n;
}

void ImagePyramid::copyIntensity0(ImageF& out) const {
  const Image<GradientPixel>& g = gradients_[0];
  out.resize(g.width(), g.height());
  for (int y = 0; y < g.height(); ++y) {
    const GradientPixel* in = g.row(y);
    float* o = out.row(y);
    for (int x = 0; x < g.width(); ++x) o[x] = in[x].intensity;
  }
}

void ImagePyramid::build(ImageView<const float> image) {
  expand();
  if (image.empty() || image.width != width(0) || image.height != height(0) ||
      image.stride < image.width) {
    throw InputError("image pyramid: input image is " + sizeString(image.width, image.height) +
                     " with stride " + std::to_string(image.stride) + ", expected " +
                     sizeString(width(0), height(0)));
  }
  ImageF& level0 = intensity_[0];
  for (int y = 0; y < image.height; ++y) {
    std::memcpy(level0.row(y), image.row(y), sizeof(float) * static_cast<std::size_t>(image.width));
  }
  computeGradients(0);
  for (int y = 0; y < image.height; ++y)
    std::memset(clipped_.row(y), 0, static_cast<std::size_t>(image.width));
  for (int l = 1; l < levels(); ++l) {
    downsample2x2(intensity_[l - 1].view(), intensity_[l].view());
    computeGradients(l);
  }
}

void ImagePyramid::markClipped(ImageView<const float> raw, float level) {
  requireFull("clipping mask", 0);
  if (raw.empty() || raw.width != width(0) || raw.height != height(0) || raw.stride < raw.width) {
    throw InputError("image pyramid: clipping source is " + sizeString(raw.width, raw.height) +
                     ", expected " + sizeString(width(0), height(0)));
  }
  for (int y = 0; y < raw.height; ++y) {
    const float* in = raw.row(y);
    std::uint8_t* out = clipped_.row(y);
    for (int x = 0; x < raw.width; ++x) out[x] = in[x] >= level ? 1 : 0;
  }
}

void ImagePyramid::computeGradients(int level) {
  const ImageF& img = intensity_[level];
  Image<GradientPixel>& grad = gradients_[level];
  const int w = img.width();
  const int h = img.height();
  for (int y = 0; y < h; ++y) {
    const float* row = img.row(y);
    GradientPixel* out = grad.row(y);
    if (y == 0 || y == h - 1) {
      for (int x = 0; x < w; ++x) out[x] = {row[x], 0.f, 0.f};
      continue;
    }
    const float* up = img.row(y - 1);
    const float* down = img.row(y + 1);
    out[0] = {row[0], 0.f, 0.f};
    for (int x = 1; x < w - 1; ++x) {
      out[x] = {row[x], 0.5f * (row[x + 1] - row[x - 1]), 0.5f * (down[x] - up[x])};
    }
    if (w > 1) out[w - 1] = {row[w - 1], 0.f, 0.f};
  }
  if (grad_mag_sq_.empty()) return;
  ImageF& mag = grad_mag_sq_[level];
  for (int y = 0; y < h; ++y) {
    const GradientPixel* g = grad.row(y);
    float* out = mag.row(y);
    for (int x = 0; x < w; ++x) out[x] = g[x].dx * g[x].dx + g[x].dy * g[x].dy;
  }
}

}  // namespace ldsm
