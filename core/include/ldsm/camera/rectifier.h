// Rectification of input images to the ideal pinhole the engine works in, following the
// semantics of DSO's camera.txt (see RectificationSpec in calibration.h and
// computeOutputIntrinsics below). Pixel convention: pixel centers at integer coordinates.
#pragma once

#include <cstdint>
#include <memory>

#include "ldsm/camera/calibration.h"
#include "ldsm/camera/camera_model.h"
#include "ldsm/image.h"

namespace ldsm {

/// Computes the output pinhole of `spec` for the input camera `input`:
///  - None: the input must be an undistorted pinhole (distortion all zero); the output is the
///    input intrinsics, rescaled when the output size differs: fx' = fx * W'/W,
///    cx' = (cx + 0.5) * W'/W - 0.5 (same for y).
///  - Crop: the largest axis-aligned window of the undistorted image plane in which every output
///    pixel samples a valid input pixel, stretched over the output size (pixel centers 0 and
///    W-1 on its borders; fx and fy are chosen independently, as DSO does).
///  - Full: the bounding box of the whole input field of view (its undistorted border) over the
///    output size; some output pixels are then invalid. Needs a field of view below 180 degrees.
///  - Explicit: spec.fx fy cx cy in output pixels or, when spec.relative, as DSO does:
///    fx * W, fy * H, cx * W - 0.5, cy * H - 0.5 (W x H the output size).
/// Crop and full outputs may not be larger than the input. Throws ldsm::InputError naming the
/// field on a non-positive output size, NaN/inf or non-positive explicit focal lengths, a
/// distorted input with mode None, or an impossible crop/full.
PinholeIntrinsics computeOutputIntrinsics(const CameraModel& input, const RectificationSpec& spec);

/// Maps input images to the output pinhole through a remap table computed once at construction
/// (bilinear interpolation). Immutable and thread-compatible; copies share the camera model.
class Rectifier {
 public:
  /// Builds the input model (makeCameraModel), the output pinhole (computeOutputIntrinsics) and
  /// the remap table. Throws ldsm::InputError on an invalid calibration or when no output pixel
  /// sees a valid input pixel.
  explicit Rectifier(const GeometricCalibration& calibration);

  const CameraModel& inputModel() const { return *input_; }
  const PinholeIntrinsics& output() const { return output_; }

  /// Rectifies an image of the input size into `out` (resized to the output size; no allocation
  /// when its capacity suffices). Output pixels without a valid input pixel get `invalid_value`.
  /// Throws ldsm::InputError when `in` does not have the input size.
  void rectify(ImageView<const std::uint8_t> in, ImageF& out, float invalid_value = 0.0f) const;
  void rectify(ImageView<const float> in, ImageF& out, float invalid_value = 0.0f) const;

  /// Input pixel coordinates sampled by each output pixel, -1 in both maps for invalid pixels.
  const ImageF& mapX() const { return map_x_; }
  const ImageF& mapY() const { return map_y_; }
  bool isValid(int x, int y) const { return map_x_(x, y) >= 0.0f; }
  int numValidPixels() const { return num_valid_; }
  /// True when rectify() is a plain copy (mode None with the input size).
  bool isIdentity() const { return identity_; }

 private:
  template <typename T>
  void remap(ImageView<const T> in, ImageF& out, float invalid_value) const;

  std::shared_ptr<const CameraModel> input_;
  PinholeIntrinsics output_;
  ImageF map_x_;
  ImageF map_y_;
  int num_valid_ = 0;
  bool identity_ = false;
};

}  // namespace ldsm
