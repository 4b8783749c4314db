// ORB descriptors (oriented rBRIEF, Rublee et al., ICCV 2011) computed at given keypoints: the
// Shi-Tomasi corners the odometry picked on a keyframe. Nothing is detected here.
//
//  * The 8-bit image (a float image is rounded and clipped to 0..255) gets a small pyramid with a
//    constant scale factor between levels. Each keypoint asks for a level (0 by default) and is
//    described on the finest level at or below it where its 31x31 patch (radius kPatchRadius)
//    fits inside the level image; a keypoint whose patch does not even fit on level 0 is dropped.
//  * Orientation: the intensity centroid of the circular patch of radius kPatchRadius on that
//    level, angle = atan2(m01, m10).
//  * Descriptor: OpenCV's rBRIEF (cv::ORB::compute on the smoothed level image), steered by that
//    angle; 256 binary tests packed as an OrbDescriptor.
// Descriptors are invariant to in-plane rotation and to affine brightness changes (up to rounding
// and clipping).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "image/gradient_pixel.h"
#include "ldsm/image.h"
#include "model/orb_descriptor.h"

namespace ldsm {

/// Settings of OrbExtractor.
struct OrbExtractorSettings {
  int levels = 3;             ///< pyramid levels, 1..8 (level 0 is the image itself)
  float scale_factor = 1.2f;  ///< size ratio of two consecutive levels, in (1, 2]
};

class OrbExtractor {
 public:
  /// Radius of the orientation patch (pixels of the keypoint's level): the patch must fit.
  static constexpr int kPatchRadius = 15;

  /// Prepares buffers for width x height images. Throws InputError when the size is not positive
  /// and ConfigError when a setting is out of range.
  OrbExtractor(int width, int height, const OrbExtractorSettings& settings = {});
  ~OrbExtractor();
  OrbExtractor(const OrbExtractor&) = delete;
  OrbExtractor& operator=(const OrbExtractor&) = delete;
  OrbExtractor(OrbExtractor&&) noexcept;
  OrbExtractor& operator=(OrbExtractor&&) noexcept;

  /// Computes descriptors at `pixels` (level-0 pixel coordinates). `levels`, when given, holds
  /// the requested pyramid level of each keypoint (same size as `pixels`; clamped to the
  /// pyramid). Fills `descriptors` and `kept` (indices into `pixels`, increasing), both cleared
  /// first, and returns the number kept. Non-finite keypoints are dropped. Throws InputError when
  /// the image size differs from the constructor's or `levels` has the wrong size.
  int compute(ImageView<const float> image, const std::vector<Eigen::Vector2f>& pixels,
              std::vector<OrbDescriptor>& descriptors, std::vector<std::uint32_t>& kept,
              const std::vector<int>* levels = nullptr);
  /// Same for the intensities of a packed (intensity, dx, dy) pyramid level.
  int compute(ImageView<const GradientPixel> image, const std::vector<Eigen::Vector2f>& pixels,
              std::vector<OrbDescriptor>& descriptors, std::vector<std::uint32_t>& kept,
              const std::vector<int>* levels = nullptr);
  /// Same for an 8-bit image.
  int compute(ImageView<const std::uint8_t> image, const std::vector<Eigen::Vector2f>& pixels,
              std::vector<OrbDescriptor>& descriptors, std::vector<std::uint32_t>& kept,
              const std::vector<int>* levels = nullptr);

  int width() const;
  int height() const;
  const OrbExtractorSettings& settings() const;
  /// Scale of a pyramid level relative to level 0 (scale_factor^level).
  float levelScale(int level) const;

 private:
  void checkSize(int width, int height, bool has_data) const;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ldsm
