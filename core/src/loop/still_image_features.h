// Keyframe-like features of a still image: Shi-Tomasi corners (the pixel selector's
// CornerDetector, same spacing and border) with ORB descriptors at those corners. With
// detection_levels = 1 these are the features the odometry gives a keyframe; more levels also
// detect corners on the ORB pyramid's coarser levels (scale orb.scale_factor^l, corner budget
// proportional to the level's area, as ORB does) and describe them there, for scale changes
// between views. Used to train vocabularies offline (ldsm vocab train) and to evaluate place
// recognition on image collections.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "features/orb_extractor.h"
#include "ldsm/image.h"
#include "loop/loop_types.h"

namespace ldsm::loop {

/// Settings of StillImageFeatures. The defaults are the best measured on rtabmap_loop84
/// (bench_place_recognition); the engine's keyframes today correspond to max_corners = 300,
/// min_corner_score = 49, detection_levels = 1.
struct StillImageFeatureSettings {
  int max_corners = 500;        ///< over all levels
  float min_corner_score = 16;  ///< Shi-Tomasi threshold (the pixel selector uses min_gradient^2)
  int detection_levels = 5;     ///< pyramid levels corners are detected on, 1..orb.levels
  OrbExtractorSettings orb{5, 1.2f};
};

/// Corners and their descriptors (only corners that got a descriptor).
struct StillFeatures {
  std::vector<Eigen::Vector2f> pixels;  ///< level-0 pixel coordinates
  std::vector<int> levels;              ///< pyramid level each was detected and described on
  std::vector<OrbDescriptor> descriptors;
};

class StillImageFeatures {
 public:
  /// Throws InputError for a non-positive size and ConfigError for bad settings.
  StillImageFeatures(int width, int height, const StillImageFeatureSettings& settings = {});
  ~StillImageFeatures();
  StillImageFeatures(const StillImageFeatures&) = delete;
  StillImageFeatures& operator=(const StillImageFeatures&) = delete;

  /// Detects corners and computes descriptors (size as at construction, else InputError).
  /// Returns the number of features.
  int compute(ImageView<const std::uint8_t> image, StillFeatures& out);

  int width() const;
  int height() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ldsm::loop
