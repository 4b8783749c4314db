#include "ldsm/camera/camera_model.h"

#include "camera_common.h"

#include <cmath>
#include <sstream>

#include "camera/camera_models.h"
#include "ldsm/error.h"
#include "math/constants.h"

namespace ldsm {
namespace {

std::string fmt(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

const char* distortionName(CameraModelType type, std::size_t i) {
  static constexpr const char* kRadTan[] = {"k1", "k2", "p1", "p2"};
  static constexpr const char* kEquidistant[] = {"k1", "k2", "k3", "k4"};
  switch (type) {
    case CameraModelType::RadTan:
      return i < 4 ? kRadTan[i] : "?";
    case CameraModelType::Equidistant:
      return i < 4 ? kEquidistant[i] : "?";
    case CameraModelType::Fov:
      return i == 0 ? "omega" : "?";
    case CameraModelType::Pinhole:
      break;
  }
  return "?";
}

}  // namespace

const char* cameraModelName(CameraModelType type) {
  switch (type) {
    case CameraModelType::Pinhole:
      return "Pinhole";
    case CameraModelType::RadTan:
      return "RadTan";
    case CameraModelType::Equidistant:
      return "EquiDistant";
    case CameraModelType::Fov:
      return "FOV";
  }
  return "unknown";
}

int numDistortionParameters(CameraModelType type) {
  switch (type) {
    case CameraModelType::Pinhole:
      return 0;
    case CameraModelType::RadTan:
    case CameraModelType::Equidistant:
      return 4;
    case CameraModelType::Fov:
      return 1;
  }
  return 0;
}

void validateIntrinsics(const CameraIntrinsics& in) {
  const std::string model = std::string(cameraModelName(in.model)) + " camera: ";
  const auto positive = [&](double v, const char* name) {
    if (!std::isfinite(v)) throw InputError(model + name + " is not finite (" + fmt(v) + ")");
    if (v <= 0) throw InputError(model + name + " must be positive (got " + fmt(v) + ")");
  };
  const auto finite = [&](double v, const char* name) {
    if (!std::isfinite(v)) throw InputError(model + name + " is not finite (" + fmt(v) + ")");
  };
  positive(in.fx, "fx");
  positive(in.fy, "fy");
  finite(in.cx, "cx");
  finite(in.cy, "cy");
  if (in.width <= 0 || in.height <= 0)
    throw InputError(model + "image size must be positive (got " + std::to_string(in.width) + "x" +
                     std::to_string(in.height) + ")");
  const int expected = numDistortionParameters(in.model);
  if (static_cast<int>(in.distortion.size()) != expected)
    throw InputError(model + "expected " + std::to_string(expected) +
                     " distortion parameters, got " + std::to_string(in.distortion.size()));
  for (std::size_t i = 0; i < in.distortion.size(); ++i)
    finite(in.distortion[i], distortionName(in.model, i));
  if (in.model == CameraModelType::Fov) {
    const double omega = in.distortion[0];
    if (omega < 0 || omega >= kPi)
      throw InputError(model + "omega must be in [0, pi) (got " + fmt(omega) + ")");
  }
}

std::unique_ptr<CameraModel> makeCameraModel(const CameraIntrinsics& intrinsics) {
  switch (intrinsics.model) {
    case CameraModelType::Pinhole:
      return std::make_unique<PinholeCamera>(intrinsics);
    case CameraModelType::RadTan:
      return std::make_unique<RadTanCamera>(intrinsics);
    case CameraModelType::Equidistant:
      return std::make_unique<EquidistantCamera>(intrinsics);
    case CameraModelType::Fov:
      return std::make_unique<FovCamera>(intrinsics);
  }
  throw InputError("camera: unknown camera model type " +
                   std::to_string(static_cast<int>(intrinsics.model)));
}

CameraModel::CameraModel(const CameraIntrinsics& intrinsics, CameraModelType expected)
    : intrinsics_(intrinsics) {
  if (intrinsics.model != expected)
    throw InputError(std::string("camera: intrinsics of a ") + cameraModelName(intrinsics.model) +
                     " model given to a " + cameraModelName(expected) + " camera");
  validateIntrinsics(intrinsics_);
}

Eigen::VectorXd CameraModel::parameters() const {
  Eigen::VectorXd p(numParameters());
  p[0] = intrinsics_.fx;
  p[1] = intrinsics_.fy;
  p[2] = intrinsics_.cx;
  p[3] = intrinsics_.cy;
  for (std::size_t i = 0; i < intrinsics_.distortion.size(); ++i)
    p[4 + static_cast<Eigen::Index>(i)] = intrinsics_.distortion[i];
  return p;
}

std::unique_ptr<CameraModel> CameraModel::withParameters(const Eigen::VectorXd& params) const {
  if (params.size() != numParameters())
    throw InputError(std::string(cameraModelName(type())) + " camera: expected " +
                     std::to_string(numParameters()) + " parameters, got " +
                     std::to_string(params.size()));
  CameraIntrinsics in = intrinsics_;
  in.fx = params[0];
  in.fy = params[1];
  in.cx = params[2];
  in.cy = params[3];
  for (std::size_t i = 0; i < in.distortion.size(); ++i)
    in.distortion[i] = params[4 + static_cast<Eigen::Index>(i)];
  return makeCameraModel(in);
}

}  // namespace ldsm
