#include "pipeline/frame_preprocessor.h"

#include <string>

#include "ldsm/error.h"

namespace ldsm {
namespace {

PhotometricCalibration selectedCalibration(const PhotometricCalibration& c,
                                           const PhotometricConfig& config) {
  PhotometricCalibration out;
  if (config.use_response && c.has_response) {
    out.has_response = true;
    out.inverse_response = c.inverse_response;
  } else {
    for (int i = 0; i < 256; ++i) out.inverse_response[i] = static_cast<float>(i);
  }
  if (config.use_vignette) out.vignette = c.vignette;
  return out;
}

}  // namespace

FramePreprocessor::FramePreprocessor(const GeometricCalibration& geometric,
                                     const PhotometricCalibration& photometric,
                                     const PhotometricConfig& config)
    : input_width_(geometric.input.width),
      input_height_(geometric.input.height),
      rectifier_(geometric),
      clipped_level_(static_cast<float>(config.clipped_level)) {
  const PhotometricCalibration used = selectedCalibration(photometric, config);
  if (used.has_response || !used.vignette.empty())
    photometric_ = std::make_unique<PhotometricModel>(used, input_width_, input_height_);
}

void FramePreprocessor::process(ImageView<const std::uint8_t> image, ImagePyramid& pyramid) {
  if (image.width != input_width_ || image.height != input_height_)
    throw InputError("frame is " + std::to_string(image.width) + "x" +
                     std::to_string(image.height) + " but the calibration is for " +
                     std::to_string(input_width_) + "x" + std::to_string(input_height_));
  if (photometric_) {
    photometric_->correct(image, corrected_);
    rectifier_.rectify(corrected_.view(), rectified_);
  } else {
    rectifier_.rectify(image, rectified_);
  }
  pyramid.build(rectified_.view());
  if (clipped_level_ > 255.f) return;
  if (photometric_) {
    rectifier_.rectify(image, rectified_raw_);
    pyramid.markClipped(rectified_raw_.view(), clipped_level_);
  } else {
    pyramid.markClipped(rectified_.view(), clipped_level_);
  }
}

}  // namespace ldsm
