// Turns a raw 8-bit camera frame into what the engine works on: photometrically corrected
// (inverse response, vignette) when a calibration is given, rectified to the ideal pinhole, and
// built into an image pyramid with gradients, row by row. Buffers are allocated once.
#pragma once

#include <memory>
#include <vector>

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
  ImageF corrected_;  ///< the photometrically corrected input (with a photometric model only)
  /// Three rectified rows: the pyramid is built row by row from them (ImageRows) instead of
  /// from a whole rectified image (1.8 MB at 1232x368), and the raw values' rows for the
  /// clipping mask go through them too.
  std::vector<float> row_ring_;
};

}  // namespace ldsm
