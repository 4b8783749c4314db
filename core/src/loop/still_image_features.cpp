#include "loop/still_image_features.h"

#include <cmath>
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "features/corner_detector.h"
#include "image/image_pyramid.h"
#include "ldsm/error.h"

namespace ldsm::loop {

/// Detection on one pyramid level.
struct LevelDetector {
  float scale = 1.f;
  int max_corners = 0;
  cv::Mat image;  ///< 8-bit level image (level 0 wraps the input)
  ImageF intensity;
  ImagePyramid gradients;
  CornerDetector detector;
  LevelDetector(int w, int h) : gradients(w, h, 1, false), detector(w, h) {
    intensity.resize(w, h);
  }
};

struct StillImageFeatures::Impl {
  int width = 0;
  int height = 0;
  StillImageFeatureSettings settings;
  std::vector<std::unique_ptr<LevelDetector>> levels;
  OrbExtractor extractor;
  std::vector<Corner> corners;
  std::vector<Eigen::Vector2f> pixels;
  std::vector<int> pixel_levels;
  std::vector<OrbDescriptor> descriptors;
  std::vector<std::uint32_t> kept;
  Impl(int w, int h, const StillImageFeatureSettings& s)
      : width(w), height(h), settings(s), extractor(w, h, s.orb) {}
};

StillImageFeatures::StillImageFeatures(int width, int height,
                                       const StillImageFeatureSettings& settings) {
  if (settings.max_corners < 1) {
    throw ConfigError("still image features: max_corners must be positive (got " +
                      std::to_string(settings.max_corners) + ")");
  }
  if (settings.detection_levels < 1 || settings.detection_levels > settings.orb.levels) {
    throw ConfigError("still image features: detection_levels must be in [1, orb.levels = " +
                      std::to_string(settings.orb.levels) + "] (got " +
                      std::to_string(settings.detection_levels) + ")");
  }
  impl_ = std::make_unique<Impl>(width, height, settings);  // validates size and ORB settings
  // Corner budget per level proportional to its area: n_l = n_0 / s^(2l).
  const double inv_area = 1.0 / (static_cast<double>(settings.orb.scale_factor) *
                                 static_cast<double>(settings.orb.scale_factor));
  double sum = 0.0;
  for (int l = 0; l < settings.detection_levels; ++l) sum += std::pow(inv_area, l);
  int assigned = 0;
  for (int l = 0; l < settings.detection_levels; ++l) {
    const float scale = impl_->extractor.levelScale(l);
    const int w = cvRound(static_cast<float>(width) / scale);
    const int h = cvRound(static_cast<float>(height) / scale);
    if (w < 2 * OrbExtractor::kPatchRadius + 2 || h < 2 * OrbExtractor::kPatchRadius + 2) break;
    auto level = std::make_unique<LevelDetector>(w, h);
    level->scale = scale;
    level->max_corners =
        l + 1 == settings.detection_levels
            ? settings.max_corners - assigned
            : static_cast<int>(std::lround(settings.max_corners * std::pow(inv_area, l) / sum));
    assigned += level->max_corners;
    impl_->levels.push_back(std::move(level));
  }
}

StillImageFeatures::~StillImageFeatures() = default;
int StillImageFeatures::width() const {
  return impl_->width;
}
int StillImageFeatures::height() const {
  return impl_->height;
}

int StillImageFeatures::compute(ImageView<const std::uint8_t> image, StillFeatures& out) {
  Impl& m = *impl_;
  out.pixels.clear();
  out.levels.clear();
  out.descriptors.clear();
  if (image.width != m.width || image.height != m.height || image.data == nullptr) {
    throw InputError("still image features: image is " + std::to_string(image.width) + "x" +
                     std::to_string(image.height) + ", expected " + std::to_string(m.width) + "x" +
                     std::to_string(m.height));
  }
  m.pixels.clear();
  m.pixel_levels.clear();
  for (std::size_t l = 0; l < m.levels.size(); ++l) {
    LevelDetector& level = *m.levels[l];
    if (l == 0) {
      level.image = cv::Mat(m.height, m.width, CV_8U, const_cast<std::uint8_t*>(image.data),
                            static_cast<std::size_t>(image.stride));
    } else {
      // Built like cv::ORB builds its pyramid, so corners sit where the descriptors look.
      cv::resize(m.levels[l - 1]->image, level.image,
                 cv::Size(level.intensity.width(), level.intensity.height()), 0, 0,
                 cv::INTER_LINEAR_EXACT);
    }
    for (int y = 0; y < level.image.rows; ++y) {
      const std::uint8_t* in = level.image.ptr<std::uint8_t>(y);
      float* f = level.intensity.row(y);
      for (int x = 0; x < level.image.cols; ++x) f[x] = static_cast<float>(in[x]);
    }
    level.gradients.build(level.intensity.view());
    CornerParams params;
    params.max_corners = level.max_corners;
    params.min_score = m.settings.min_corner_score;
    level.detector.detect(level.gradients.gradients(0), params, m.corners);
    for (const Corner& c : m.corners) {
      // Level pixel centres map to level 0 by the same scaling cv::ORB uses.
      m.pixels.emplace_back(c.u * level.scale, c.v * level.scale);
      m.pixel_levels.push_back(static_cast<int>(l));
    }
  }
  m.extractor.compute(image, m.pixels, m.descriptors, m.kept, &m.pixel_levels);
  out.descriptors = m.descriptors;
  out.pixels.reserve(m.kept.size());
  out.levels.reserve(m.kept.size());
  for (std::uint32_t i : m.kept) {
    out.pixels.push_back(m.pixels[i]);
    out.levels.push_back(m.pixel_levels[i]);
  }
  return static_cast<int>(out.pixels.size());
}

}  // namespace ldsm::loop
