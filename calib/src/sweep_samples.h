// The pixel samples of an exposure sweep (private to calib/src): validated images sorted by
// exposure time, a regular subsample of their pixels, which samples are usable, and the check
// that brightness follows exposure.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "ldsm/calib/exposed_image.h"

namespace ldsm::calib::detail {

class SweepSamples {
 public:
  /// Throws ldsm::InputError "<source>: ..." on fewer than 3 images, an empty image, images of
  /// different sizes, an exposure time that is not positive and finite, or fewer than 3 images
  /// with at least min_usable_fraction of their pixels in [min_value, max_value] (naming how
  /// many are saturated or dark and what to do).
  SweepSamples(const std::vector<ExposedImage>& images, int min_value, int max_value,
               int max_pixels, double min_usable_fraction, const std::string& source);

  int imageCount() const { return static_cast<int>(order_.size()); }
  std::size_t pixelCount() const { return pixels_; }
  /// Usable image i in order of increasing exposure.
  double exposure(int i) const { return exposures_[static_cast<std::size_t>(i)]; }
  const std::string& name(int i) const { return names_[static_cast<std::size_t>(i)]; }
  /// Index of usable image i in the input list.
  std::size_t inputIndex(int i) const { return order_[static_cast<std::size_t>(i)]; }
  std::uint8_t value(int i, std::size_t x) const { return values_[index(i, x)]; }
  /// Sample x of image i is in [min_value, max_value], and the pixel was not (nearly) saturated
  /// in a shorter exposure nor (nearly) black in a longer one (clipped values that noise pulled
  /// into range).
  bool valid(int i, std::size_t x) const { return valid_[index(i, x)] != 0; }
  /// Longest / shortest usable exposure.
  double exposureRange() const { return exposures_.back() / exposures_.front(); }
  /// Mean fraction of saturated and of dark pixels over the usable images.
  double saturatedFraction() const { return saturated_fraction_; }
  double darkFraction() const { return dark_fraction_; }

  /// Compares each image with the first one exposed at least 1.5x longer: over the pixels valid
  /// in both and clear of the ends of the range (16 .. max_value - 8), the median change must be
  /// positive. Returns an empty string when it is, otherwise a message naming the worst pair and
  /// what to do.
  std::string brightnessCheck() const;

  /// Names of the images skipped as almost all saturated, or almost all dark.
  const std::vector<std::string>& saturatedImages() const { return saturated_names_; }
  const std::vector<std::string>& darkImages() const { return dark_names_; }

 private:
  std::size_t index(int i, std::size_t x) const {
    return static_cast<std::size_t>(i) * pixels_ + x;
  }

  int min_value_, max_value_;
  std::size_t pixels_ = 0;
  double saturated_fraction_ = 0.0, dark_fraction_ = 0.0;
  std::vector<std::size_t> order_;
  std::vector<double> exposures_;
  std::vector<std::string> names_;
  std::vector<std::uint8_t> values_;  // image-major
  std::vector<std::uint8_t> valid_;
  std::vector<std::string> saturated_names_, dark_names_;
};

}  // namespace ldsm::calib::detail
