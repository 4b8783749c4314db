// Turns a raw 8-bit camera frame into what the engine works on: photometrically corrected
// (inverse response, vignette) when a calibration is given, rectified to the ideal pinhole, and
// built into an image pyramid with gradients. Buffers are allocated once.
#pragma once

#include <memory>

#include "image/image_pyramid.h"
#include "ldsm/camera/calibration.h"
#include "ldsm/camera/photometric_model.h"
#include "ldsm/camera/rectifier.h"
#include "ldsm/config.h"

namespace ldsm {

class FramePreprocessor {
 public:
  FramePreprocessor(const GeometricCalibration& geometric,
                    const PhotometricCalibration& photometric, const PhotometricConfig& config);

  /// Input size the frames must have.
  int inputWidth() const { return input_width_; }
  int inputHeight() const { return input_height_; }
  const PinholeIntrinsics& output() const { return rectifier_.output(); }
  bool photometricallyCalibrated() const { return photometric_ != nullptr; }

  /// Corrects and rectifies `image` into `pyramid` (of the output size) and marks the pixels
  /// whose raw value reaches the config's clipped_level. Throws InputError when the image size
  /// differs from the calibration's.
  void process(ImageView<const std::uint8_t> image, ImagePyramid& pyramid);

 private:
  int input_width_;
  int input_height_;
  Rectifier rectifier_;
  std::unique_ptr<PhotometricModel> photometric_;
  float clipped_level_;
  ImageF corrected_;
  ImageF rectified_;
  ImageF rectified_raw_;  ///< raw values in the output geometry (with a photometric model only)
};

}  // namespace ldsm
