// Projection models of the input camera: pinhole, radial-tangential (OpenCV), equidistant
// (Kannala-Brandt, OpenCV fisheye) and FOV/ATAN (TUM-Mono, PTAM).
//
// Pixel convention (the same as DSO and OpenCV): the center of pixel (i, j) has the coordinate
// (i, j); an image of width x height covers [-0.5, width - 0.5] x [-0.5, height - 0.5], and
// bilinear interpolation is possible for coordinates in [0, width - 1] x [0, height - 1].
//
// Intrinsic parameters are ordered fx fy cx cy followed by the model's distortion parameters in
// the order of CameraModelType (see calibration.h).
#pragma once

#include <Eigen/Core>
#include <memory>

#include "ldsm/camera/calibration.h"

namespace ldsm {

/// A camera projection model. Immutable after construction, cheap to copy through clone().
class CameraModel {
 public:
  using PointJacobian = Eigen::Matrix<double, 2, 3>;
  using IntrinsicsJacobian = Eigen::Matrix<double, 2, Eigen::Dynamic>;

  virtual ~CameraModel() = default;

  virtual std::unique_ptr<CameraModel> clone() const = 0;

  CameraModelType type() const { return intrinsics_.model; }
  const CameraIntrinsics& intrinsics() const { return intrinsics_; }
  int width() const { return intrinsics_.width; }
  int height() const { return intrinsics_.height; }

  /// Number of intrinsic parameters (4 + number of distortion parameters).
  int numParameters() const { return 4 + static_cast<int>(intrinsics_.distortion.size()); }
  /// The parameters fx fy cx cy d0 d1 ... as one vector.
  Eigen::VectorXd parameters() const;
  /// A model of the same type and size with other parameters (validated like makeCameraModel).
  std::unique_ptr<CameraModel> withParameters(const Eigen::VectorXd& params) const;

  /// Projects a point in camera coordinates to pixel coordinates. Returns false (and leaves the
  /// outputs untouched) when the point is behind the camera or outside the domain in which the
  /// model is invertible. Does not check the image bounds (see inImage()). `J`, when given,
  /// receives d(px)/d(p_cam).
  virtual bool project(const Eigen::Vector3d& p_cam, Eigen::Vector2d* px,
                       PointJacobian* J = nullptr) const = 0;

  /// Back-projects a pixel to a unit-norm bearing vector in camera coordinates. Returns false
  /// when the pixel is outside the model's valid domain or (for the iterative models) the
  /// undistortion did not converge.
  virtual bool unproject(const Eigen::Vector2d& px, Eigen::Vector3d* ray) const = 0;

  /// Jacobian (2 x numParameters()) of project() with respect to the intrinsic parameters.
  /// Returns false where project() would.
  virtual bool intrinsicsJacobian(const Eigen::Vector3d& p_cam, IntrinsicsJacobian* J) const = 0;

  /// True when px lies within [margin, width - 1 - margin] x [margin, height - 1 - margin].
  bool inImage(const Eigen::Vector2d& px, double margin = 0.0) const {
    return px.x() >= margin && px.y() >= margin && px.x() <= width() - 1 - margin &&
           px.y() <= height() - 1 - margin;
  }

 protected:
  /// Validates the intrinsics (see validateIntrinsics) and checks that they are of `expected`.
  CameraModel(const CameraIntrinsics& intrinsics, CameraModelType expected);
  CameraModel(const CameraModel&) = default;
  CameraModel& operator=(const CameraModel&) = default;

  /// Applies fx fy cx cy to normalized (distorted) coordinates.
  Eigen::Vector2d toPixel(const Eigen::Vector2d& xy) const {
    return {intrinsics_.fx * xy.x() + intrinsics_.cx, intrinsics_.fy * xy.y() + intrinsics_.cy};
  }
  /// Inverse of toPixel().
  Eigen::Vector2d fromPixel(const Eigen::Vector2d& px) const {
    return {(px.x() - intrinsics_.cx) / intrinsics_.fx, (px.y() - intrinsics_.cy) / intrinsics_.fy};
  }

  CameraIntrinsics intrinsics_;
};

/// Name of a model as written in DSO camera.txt files: Pinhole, RadTan, EquiDistant, FOV.
const char* cameraModelName(CameraModelType type);

/// Number of distortion parameters of a model (0, 4, 4, 1).
int numDistortionParameters(CameraModelType type);

/// Throws ldsm::InputError naming the offending field unless every value is finite, fx and fy are
/// positive, width and height are positive, the distortion has the right number of parameters
/// and they are in range (FOV: 0 <= omega < pi).
void validateIntrinsics(const CameraIntrinsics& intrinsics);

/// Builds the model described by `intrinsics` (validated as above).
std::unique_ptr<CameraModel> makeCameraModel(const CameraIntrinsics& intrinsics);

}  // namespace ldsm
