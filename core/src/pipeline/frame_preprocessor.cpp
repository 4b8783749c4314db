#include "pipeline/frame_preprocessor.h"

#include <limits>
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

// The rectified rows of an input image, into a ring of three rows.
template <typename T>
class RectifiedRows final : public ImageRows {
 public:
  RectifiedRows(const Rectifier& rectifier, ImageView<const T> input, std::vector<float>& ring)
      : rectifier_(rectifier), input_(input), ring_(ring) {}
  const float* row(int y) override {
    const auto width = static_cast<std::size_t>(rectifier_.output().width);
    float* out = ring_.data() + static_cast<std::size_t>(y % 3) * width;
    rectifier_.rectifyRow(input_, y, out);
    return out;
  }

 private:
  const Rectifier& rectifier_;
  ImageView<const T> input_;
  std::vector<float>& ring_;
};

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
  const PinholeIntrinsics& out = rectifier_.output();
  if (pyramid.width(0) != out.width || pyramid.height(0) != out.height)
    throw InputError("image pyramid is " + std::to_string(pyramid.width(0)) + "x" +
                     std::to_string(pyramid.height(0)) + " but the rectified frames are " +
                     std::to_string(out.width) + "x" + std::to_string(out.height));
  row_ring_.resize(3 * static_cast<std::size_t>(out.width));
  if (photometric_) {
    photometric_->correct(image, corrected_);
    RectifiedRows<float> rows(rectifier_, corrected_.view(), row_ring_);
    pyramid.build(rows);
  } else {
    // The rectified raw values themselves give the clipping mask, made while each row is at hand.
    RectifiedRows<std::uint8_t> rows(rectifier_, image, row_ring_);
    pyramid.build(rows,
                  clipped_level_ > 255.f ? std::numeric_limits<float>::infinity() : clipped_level_);
    return;
  }
  if (clipped_level_ > 255.f) return;
  RectifiedRows<std::uint8_t> raw(rectifier_, image, row_ring_);
  pyramid.markClipped(raw, clipped_level_);
}

}  // namespace ldsm
