#include "sweep_samples.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

#include "ldsm/error.h"

namespace ldsm::calib::detail {
namespace {

std::string fmt(double v, int decimals) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
  return buf;
}

}  // namespace

SweepSamples::SweepSamples(const std::vector<ExposedImage>& images, int min_value, int max_value,
                           int max_pixels, double min_usable_fraction, const std::string& source)
    : min_value_(min_value), max_value_(max_value) {
  if (images.size() < 3)
    throw InputError(source + ": an exposure sweep needs at least 3 images (has " +
                     std::to_string(images.size()) + ")");
  const int W = images.front().image.width, H = images.front().image.height;
  for (const ExposedImage& im : images) {
    if (im.image.empty()) throw InputError(source + ": " + im.name + ": empty image");
    if (im.image.width != W || im.image.height != H)
      throw InputError(source + ": " + im.name + " is " + std::to_string(im.image.width) + "x" +
                       std::to_string(im.image.height) + " but " + images.front().name + " is " +
                       std::to_string(W) + "x" + std::to_string(H));
    if (!(std::isfinite(im.exposure_ms) && im.exposure_ms > 0.0))
      throw InputError(source + ": " + im.name + " has exposure time " + fmt(im.exposure_ms, 4) +
                       " ms; every image needs a positive exposure time (the third column of "
                       "times.txt, in milliseconds)");
  }
  // A regular subsample of at most max_pixels pixels, the same in every image.
  const int stride =
      std::max(1, static_cast<int>(std::ceil(std::sqrt(static_cast<double>(W) * H / max_pixels))));
  const int sw = (W + stride - 1) / stride, sh = (H + stride - 1) / stride;
  pixels_ = static_cast<std::size_t>(sw) * static_cast<std::size_t>(sh);

  // Images with too few pixels in range are skipped.
  std::vector<std::string> saturated, dark;
  std::vector<std::size_t> usable;
  for (std::size_t i = 0; i < images.size(); ++i) {
    std::size_t n_dark = 0, n_sat = 0;
    const auto& v = images[i].image;
    for (int y = 0; y < H; y += stride)
      for (int x = 0; x < W; x += stride) {
        n_dark += v(x, y) < min_value;
        n_sat += v(x, y) > max_value;
      }
    const double in_range = 1.0 - static_cast<double>(n_dark + n_sat) / pixels_;
    if (in_range >= min_usable_fraction) {
      usable.push_back(i);
      saturated_fraction_ += static_cast<double>(n_sat) / pixels_;
      dark_fraction_ += static_cast<double>(n_dark) / pixels_;
    } else
      (n_sat > n_dark ? saturated : dark).push_back(images[i].name);
  }
  if (usable.size() < 3)
    throw InputError(source + ": only " + std::to_string(usable.size()) + " of " +
                     std::to_string(images.size()) + " images have usable pixels (" +
                     std::to_string(saturated.size()) + " almost all saturated" +
                     (saturated.empty() ? "" : ": use shorter exposures or less light") + "; " +
                     std::to_string(dark.size()) + " almost all dark" +
                     (dark.empty() ? "" : ": use longer exposures or more light") +
                     "); the sweep must go from nearly black to nearly white images");
  saturated_names_ = saturated;
  dark_names_ = dark;

  saturated_fraction_ /= static_cast<double>(usable.size());
  dark_fraction_ /= static_cast<double>(usable.size());
  std::stable_sort(usable.begin(), usable.end(), [&](std::size_t a, std::size_t b) {
    return images[a].exposure_ms < images[b].exposure_ms;
  });
  order_ = usable;
  values_.resize(order_.size() * pixels_);
  for (std::size_t i = 0; i < order_.size(); ++i) {
    const ExposedImage& im = images[order_[i]];
    exposures_.push_back(im.exposure_ms);
    names_.push_back(im.name);
    std::uint8_t* out = values_.data() + i * pixels_;
    for (int y = 0; y < H; y += stride)
      for (int x = 0; x < W; x += stride) *out++ = im.image(x, y);
  }

  // Valid samples: in range, not from the exposure on which the pixel first came close to 255
  // (clipped, noise may pull it back into range), not up to the last one on which it was close
  // to 0. "Close" is 4 grey levels beyond the range: far enough that noise rarely moves a clipped
  // value into the range, and that a value in range is rarely discarded for a noisy neighbour
  // exposure (which would bias the estimate at the ends of the range).
  valid_.assign(values_.size(), 0);
  const int n = imageCount();
  const int saturated_onset = std::min(255, max_value + 4), dark_onset = std::max(0, min_value - 4);
  for (std::size_t x = 0; x < pixels_; ++x) {
    double t_saturated = std::numeric_limits<double>::infinity(), t_dark = 0.0;
    for (int i = 0; i < n; ++i) {
      const int v = value(i, x);
      if (v >= saturated_onset) t_saturated = std::min(t_saturated, exposure(i));
      if (v <= dark_onset) t_dark = std::max(t_dark, exposure(i));
    }
    for (int i = 0; i < n; ++i) {
      const int v = value(i, x);
      valid_[index(i, x)] =
          v >= min_value && v <= max_value && exposure(i) < t_saturated && exposure(i) > t_dark;
    }
  }
}

std::string SweepSamples::brightnessCheck() const {
  const int n = imageCount();
  const int lo = std::max(min_value_, 16), hi = max_value_ - 8;
  int worst_median = 1, worst_a = -1, worst_b = -1, bad_pairs = 0;
  double worst_up = 0.0, worst_down = 0.0;
  for (int a = 0; a < n; ++a) {
    int b = a + 1;
    while (b < n && exposure(b) < 1.5 * exposure(a)) ++b;
    if (b >= n) break;
    // Histogram of the changes of the pixels valid in both and clear of the ends of the range
    // (near black and near saturation a longer exposure may change a value by less than the
    // noise).
    std::array<std::size_t, 511> changes{};
    std::size_t both = 0;
    for (std::size_t x = 0; x < pixels_; ++x) {
      if (!valid(a, x) || !valid(b, x)) continue;
      const int va = value(a, x), vb = value(b, x);
      if (std::min(va, vb) < lo || std::max(va, vb) > hi) continue;
      ++changes[static_cast<std::size_t>(vb - va + 255)];
      ++both;
    }
    if (both < std::max<std::size_t>(100, pixels_ / 100)) continue;
    std::size_t below = 0;
    int median = -255;
    while (below + changes[static_cast<std::size_t>(median + 255)] <= both / 2)
      below += changes[static_cast<std::size_t>(median++ + 255)];
    if (median > 0) continue;
    ++bad_pairs;
    if (median < worst_median || worst_a < 0) {
      worst_median = median;
      worst_a = a;
      worst_b = b;
      std::size_t down = 0, up = 0;
      for (int d = -255; d <= 255; ++d)
        (d < 0 ? down : up) += d == 0 ? 0 : changes[static_cast<std::size_t>(d + 255)];
      worst_down = static_cast<double>(down) / both;
      worst_up = static_cast<double>(up) / both;
    }
  }
  if (bad_pairs == 0) return {};
  return "brightness does not follow exposure: from " + name(worst_a) + " (" +
         fmt(exposure(worst_a), 3) + " ms) to " + name(worst_b) + " (" + fmt(exposure(worst_b), 3) +
         " ms, " + fmt(exposure(worst_b) / exposure(worst_a), 1) +
         "x longer) the median pixel changed by " + std::to_string(worst_median) + " (" +
         fmt(100 * worst_up, 0) + "% of the pixels got brighter, " + fmt(100 * worst_down, 0) +
         "% darker; " + std::to_string(bad_pairs) +
         " such pairs). Auto-exposure or auto-gain seems on, or the exposure times do not "
         "belong to the images: lock exposure and gain (e.g. v4l2-ctl -c auto_exposure=1 -c "
         "gain_automatic=0), keep the scene and light still, and record the sweep again";
}

}  // namespace ldsm::calib::detail
