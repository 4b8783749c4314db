#include "features/orb_extractor.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "ldsm/error.h"
#include "math/constants.h"

namespace ldsm {
namespace {

constexpr int kMaxLevels = 8;
constexpr int kRadius = OrbExtractor::kPatchRadius;
constexpr int kDescriptorBytes = 32;

/// Half-widths of the rows of the circular orientation patch: |dx| <= halfWidth(|dy|).
std::array<int, kRadius + 1> circleHalfWidths() {
  std::array<int, kRadius + 1> w{};
  for (int dy = 0; dy <= kRadius; ++dy) {
    w[static_cast<std::size_t>(dy)] =
        static_cast<int>(std::floor(std::sqrt(static_cast<double>(kRadius * kRadius - dy * dy))));
  }
  return w;
}

/// Intensity-centroid orientation (degrees, [0, 360)) of the circular patch centred at (x, y).
float centroidAngle(const cv::Mat& image, int x, int y, const std::array<int, kRadius + 1>& half) {
  long m10 = 0;
  long m01 = 0;
  for (int dy = -kRadius; dy <= kRadius; ++dy) {
    const std::uint8_t* row = image.ptr<std::uint8_t>(y + dy);
    const int hw = half[static_cast<std::size_t>(std::abs(dy))];
    long row_sum = 0;
    for (int dx = -hw; dx <= hw; ++dx) {
      const long v = row[x + dx];
      m10 += dx * v;
      row_sum += v;
    }
    m01 += dy * row_sum;
  }
  float deg = static_cast<float>(std::atan2(static_cast<double>(m01), static_cast<double>(m10)) *
                                 (180.0 / kPi));
  if (deg < 0.f) deg += 360.f;
  if (deg >= 360.f) deg -= 360.f;
  return deg;
}

OrbDescriptor packDescriptor(const std::uint8_t* bytes) {
  OrbDescriptor d{};
  for (int w = 0; w < 4; ++w) {
    std::uint64_t word = 0;
    for (int b = 0; b < 8; ++b) word |= static_cast<std::uint64_t>(bytes[8 * w + b]) << (8 * b);
    d[static_cast<std::size_t>(w)] = word;
  }
  return d;
}

}  // namespace

struct OrbExtractor::Impl {
  int width = 0;
  int height = 0;
  OrbExtractorSettings settings;
  std::array<int, kRadius + 1> half_widths{};
  std::vector<float> scales;  ///< scale_factor^level
  std::vector<cv::Size> level_sizes;
  cv::Ptr<cv::ORB> orb;
  cv::Mat gray;                  ///< 8-bit copy of a float image
  std::vector<cv::Mat> pyramid;  ///< levels 1.. (level 0 is the input)
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptor_rows;

  int compute(const cv::Mat& image, const std::vector<Eigen::Vector2f>& pixels,
              std::vector<OrbDescriptor>& descriptors, std::vector<std::uint32_t>& kept,
              const std::vector<int>* levels);
  bool fits(float u, float v, int level) const {
    const float inv = 1.f / scales[static_cast<std::size_t>(level)];
    const int x = cvRound(u * inv);
    const int y = cvRound(v * inv);
    const cv::Size& s = level_sizes[static_cast<std::size_t>(level)];
    return x >= kRadius && y >= kRadius && x <= s.width - 1 - kRadius &&
           y <= s.height - 1 - kRadius;
  }
};

OrbExtractor::OrbExtractor(int width, int height, const OrbExtractorSettings& settings)
    : impl_(std::make_unique<Impl>()) {
  if (width <= 0 || height <= 0) {
    throw InputError("OrbExtractor: image size must be positive (got " + std::to_string(width) +
                     "x" + std::to_string(height) + ")");
  }
  if (settings.levels < 1 || settings.levels > kMaxLevels) {
    throw ConfigError("OrbExtractor: levels must be in [1, " + std::to_string(kMaxLevels) +
                      "] (got " + std::to_string(settings.levels) + ")");
  }
  if (!(settings.scale_factor > 1.f && settings.scale_factor <= 2.f)) {
    throw ConfigError("OrbExtractor: scale_factor must be in (1, 2] (got " +
                      std::to_string(settings.scale_factor) + ")");
  }
  Impl& m = *impl_;
  m.width = width;
  m.height = height;
  m.settings = settings;
  m.half_widths = circleHalfWidths();
  for (int l = 0; l < settings.levels; ++l) {
    const float s = std::pow(settings.scale_factor, static_cast<float>(l));
    m.scales.push_back(s);
    // The level sizes cv::ORB uses for its own pyramid.
    m.level_sizes.emplace_back(cvRound(static_cast<float>(width) / s),
                               cvRound(static_cast<float>(height) / s));
  }
  // The border filter of cv::ORB (edgeThreshold) is looser than fits(); its image padding
  // (edgeThreshold pixels) plus the kept distance covers the rotated test pattern.
  m.orb = cv::ORB::create(500, settings.scale_factor, settings.levels, kRadius, 0, 2,
                          cv::ORB::HARRIS_SCORE, 2 * kRadius + 1, 20);
  m.gray.create(height, width, CV_8U);
  m.pyramid.resize(static_cast<std::size_t>(settings.levels));
}

OrbExtractor::~OrbExtractor() = default;
OrbExtractor::OrbExtractor(OrbExtractor&&) noexcept = default;
OrbExtractor& OrbExtractor::operator=(OrbExtractor&&) noexcept = default;

int OrbExtractor::width() const {
  return impl_->width;
}
int OrbExtractor::height() const {
  return impl_->height;
}
const OrbExtractorSettings& OrbExtractor::settings() const {
  return impl_->settings;
}
float OrbExtractor::levelScale(int level) const {
  return impl_->scales[static_cast<std::size_t>(std::clamp(level, 0, impl_->settings.levels - 1))];
}

namespace {

/// A float intensity as the 8-bit image the descriptors are computed on (NaN becomes 0).
std::uint8_t toGrey(float v) {
  return v > 0.f ? static_cast<std::uint8_t>(std::min(v, 255.f) + 0.5f) : 0;
}

}  // namespace

int OrbExtractor::compute(ImageView<const float> image, const std::vector<Eigen::Vector2f>& pixels,
                          std::vector<OrbDescriptor>& descriptors, std::vector<std::uint32_t>& kept,
                          const std::vector<int>* levels) {
  Impl& m = *impl_;
  checkSize(image.width, image.height, image.data != nullptr);
  for (int y = 0; y < m.height; ++y) {
    const float* in = image.row(y);
    std::uint8_t* out = m.gray.ptr<std::uint8_t>(y);
    for (int x = 0; x < m.width; ++x) out[x] = toGrey(in[x]);
  }
  return m.compute(m.gray, pixels, descriptors, kept, levels);
}

int OrbExtractor::compute(ImageView<const GradientPixel> image,
                          const std::vector<Eigen::Vector2f>& pixels,
                          std::vector<OrbDescriptor>& descriptors, std::vector<std::uint32_t>& kept,
                          const std::vector<int>* levels) {
  Impl& m = *impl_;
  checkSize(image.width, image.height, image.data != nullptr);
  for (int y = 0; y < m.height; ++y) {
    const GradientPixel* in = image.row(y);
    std::uint8_t* out = m.gray.ptr<std::uint8_t>(y);
    for (int x = 0; x < m.width; ++x) out[x] = toGrey(in[x].intensity);
  }
  return m.compute(m.gray, pixels, descriptors, kept, levels);
}

void OrbExtractor::checkSize(int width, int height, bool has_data) const {
  const Impl& m = *impl_;
  if (width != m.width || height != m.height || !has_data) {
    throw InputError("OrbExtractor: image is " + std::to_string(width) + "x" +
                     std::to_string(height) + ", expected " + std::to_string(m.width) + "x" +
                     std::to_string(m.height));
  }
}

int OrbExtractor::compute(ImageView<const std::uint8_t> image,
                          const std::vector<Eigen::Vector2f>& pixels,
                          std::vector<OrbDescriptor>& descriptors, std::vector<std::uint32_t>& kept,
                          const std::vector<int>* levels) {
  Impl& m = *impl_;
  checkSize(image.width, image.height, image.data != nullptr);
  const cv::Mat wrapped(m.height, m.width, CV_8U, const_cast<std::uint8_t*>(image.data),
                        static_cast<std::size_t>(image.stride));
  return m.compute(wrapped, pixels, descriptors, kept, levels);
}

int OrbExtractor::Impl::compute(const cv::Mat& image, const std::vector<Eigen::Vector2f>& pixels,
                                std::vector<OrbDescriptor>& descriptors,
                                std::vector<std::uint32_t>& kept,
                                const std::vector<int>* requested) {
  descriptors.clear();
  kept.clear();
  if (requested != nullptr && requested->size() != pixels.size()) {
    throw InputError("OrbExtractor: " + std::to_string(requested->size()) + " levels for " +
                     std::to_string(pixels.size()) + " keypoints");
  }
  // Choose each keypoint's level: the finest at or below the requested one where it fits.
  keypoints.clear();
  int top_level = 0;
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    const float u = pixels[i].x();
    const float v = pixels[i].y();
    if (!std::isfinite(u) || !std::isfinite(v)) continue;
    // cv::ORB's own filter on level-0 coordinates (edgeThreshold = kRadius).
    if (u < kRadius || v < kRadius || u >= width - kRadius || v >= height - kRadius) continue;
    int level = requested != nullptr ? std::clamp((*requested)[i], 0, settings.levels - 1) : 0;
    while (level >= 0 && !fits(u, v, level)) --level;
    if (level < 0) continue;
    top_level = std::max(top_level, level);
    const float scale = scales[static_cast<std::size_t>(level)];
    keypoints.emplace_back(cv::Point2f(u, v), (2 * kRadius + 1) * scale, 0.f, 0.f, level,
                           static_cast<int>(i));
  }
  if (keypoints.empty()) return 0;

  // Orientation on the (unsmoothed) level images, built like cv::ORB builds its pyramid.
  for (int l = 1; l <= top_level; ++l) {
    const cv::Mat& prev = l == 1 ? image : pyramid[static_cast<std::size_t>(l - 1)];
    cv::resize(prev, pyramid[static_cast<std::size_t>(l)], level_sizes[static_cast<std::size_t>(l)],
               0, 0, cv::INTER_LINEAR_EXACT);
  }
  for (cv::KeyPoint& kp : keypoints) {
    const cv::Mat& level_image =
        kp.octave == 0 ? image : pyramid[static_cast<std::size_t>(kp.octave)];
    const float inv = 1.f / scales[static_cast<std::size_t>(kp.octave)];
    kp.angle =
        centroidAngle(level_image, cvRound(kp.pt.x * inv), cvRound(kp.pt.y * inv), half_widths);
  }

  orb->compute(image, keypoints, descriptor_rows);
  if (descriptor_rows.rows != static_cast<int>(keypoints.size()) ||
      (descriptor_rows.rows > 0 &&
       (descriptor_rows.cols != kDescriptorBytes || descriptor_rows.type() != CV_8U))) {
    throw Error("OrbExtractor: unexpected descriptor layout from cv::ORB");
  }
  // cv::ORB keeps the order of the keypoints it does not filter out; sort by index anyway.
  std::vector<std::pair<std::uint32_t, int>> order;
  order.reserve(keypoints.size());
  for (int r = 0; r < descriptor_rows.rows; ++r) {
    order.emplace_back(static_cast<std::uint32_t>(keypoints[static_cast<std::size_t>(r)].class_id),
                       r);
  }
  std::sort(order.begin(), order.end());
  descriptors.reserve(order.size());
  kept.reserve(order.size());
  for (const auto& [index, row] : order) {
    kept.push_back(index);
    descriptors.push_back(packDescriptor(descriptor_rows.ptr<std::uint8_t>(row)));
  }
  return static_cast<int>(kept.size());
}

}  // namespace ldsm
