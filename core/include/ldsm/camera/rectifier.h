// Rectification of input images to the ideal pinhole the engine works in, following the
// semantics of DSO's camera.txt (see RectificationSpec in calibration.h and
// computeOutputIntrinsics below). Pixel convention: pixel centers at integer coordinates.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>

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
/// When the table is separable (input column a function of the output column only, input row of
/// the output row only: an undistorted pinhole input, as KITTI's), only one row and one column of
/// it are kept (8 bytes per output pixel otherwise: 3.6 MB at 1232x368), with identical results.
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
  /// Output row `v` alone into `out` (output width floats): row v of what rectify() makes, for
  /// consumers that take an image row by row. Throws ldsm::InputError like rectify(), and when v
  /// is not an output row.
  void rectifyRow(ImageView<const std::uint8_t> in, int v, float* out,
                  float invalid_value = 0.0f) const;
  void rectifyRow(ImageView<const float> in, int v, float* out, float invalid_value = 0.0f) const;

  /// The input pixel output pixel (x, y) samples; (-1, -1) when it sees no input.
  Eigen::Vector2f inputPixel(int x, int y) const;
  bool isValid(int x, int y) const { return inputPixel(x, y).x() >= 0.0f; }
  /// True when the table is kept as one row and one column (see above).
  bool isSeparable() const { return separable_; }
  /// Bytes held by the remap table.
  std::size_t tableBytes() const;
  int numValidPixels() const { return num_valid_; }
  /// True when rectify() is a plain copy (mode None with the input size).
  bool isIdentity() const { return identity_; }

 private:
  template <typename T>
  void remap(ImageView<const T> in, ImageF& out, float invalid_value) const;
  template <typename T>
  void checkInput(ImageView<const T> in) const;
  /// Row v of the output (the input checked).
  template <typename T>
  void remapRow(ImageView<const T> in, int v, float* out, float invalid_value) const;

  std::shared_ptr<const CameraModel> input_;
  PinholeIntrinsics output_;
  /// Keeps only column_x_ and row_y_ when the full maps are separable.
  void keepSeparableTable();

  ImageF map_x_;  ///< empty when separable_
  ImageF map_y_;
  std::vector<float> column_x_;  ///< separable: the input x of each output column (-1: none)
  std::vector<float> row_y_;     ///< separable: the input y of each output row (-1: none)
  /// separable: each output column's clamped input column and weight (-1: none), as
  /// camera/remap_bilinear.h's separable row remap takes them
  std::vector<std::int32_t> column_x0_;
  std::vector<float> column_ax_;
  int num_valid_ = 0;
  bool identity_ = false;
  bool separable_ = false;
};

}  // namespace ldsm
