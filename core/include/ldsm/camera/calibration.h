// Calibration as plain values: the geometric camera model of the input images, the ideal pinhole
// the engine works in (DSO camera.txt semantics), and the photometric calibration.
// Parsing and writing files lives in ldsm::calib; the models and rectifier built from these
// values live in core/src/camera.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "ldsm/image.h"

namespace ldsm {

enum class CameraModelType {
  Pinhole,      ///< fx fy cx cy
  RadTan,       ///< fx fy cx cy k1 k2 p1 p2  (OpenCV / EuRoC radial-tangential)
  Equidistant,  ///< fx fy cx cy k1 k2 k3 k4  (Kannala-Brandt fisheye)
  Fov,          ///< fx fy cx cy omega         (FOV / ATAN model of TUM-Mono)
};

/// Intrinsics in pixels of an input image of width x height. `distortion` holds the model's
/// extra parameters in the order listed above (empty for Pinhole).
struct CameraIntrinsics {
  CameraModelType model = CameraModelType::Pinhole;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  std::vector<double> distortion;
  int width = 0;
  int height = 0;
};

/// How the rectified (ideal pinhole) output is chosen, DSO camera.txt line 3:
/// `crop` keeps only valid pixels, `full` keeps the whole input field of view, `none` uses the
/// input intrinsics unchanged (pinhole input only), `explicit` gives fx fy cx cy.
enum class OutputMode { Crop, Full, None, Explicit };

struct RectificationSpec {
  OutputMode mode = OutputMode::None;
  /// Explicit output pinhole: in pixels of the output image, or relative to the output size
  /// (fx/width, fy/height, cx/width, cy/height) when `relative` is true (DSO: all values < 1).
  double fx = 0, fy = 0, cx = 0, cy = 0;
  bool relative = false;
  int width = 0;   ///< output width in pixels
  int height = 0;  ///< output height in pixels
};

/// The whole geometric calibration of one camera as given by a DSO camera.txt (or converted from
/// a Kalibr/EuRoC YAML or KITTI calib.txt).
struct GeometricCalibration {
  CameraIntrinsics input;
  RectificationSpec output;
};

/// An ideal pinhole in pixels: what the engine sees after rectification.
struct PinholeIntrinsics {
  double fx = 0, fy = 0, cx = 0, cy = 0;
  int width = 0;
  int height = 0;
};

/// Photometric calibration: I = G(t * V(x) * B(x)). `inverse_response[v]` maps a pixel value v
/// to irradiance units (G^-1), `vignette` is V(x) in [0, 1] at input resolution (empty: none).
struct PhotometricCalibration {
  bool has_response = false;
  std::array<float, 256> inverse_response{};
  ImageF vignette;  ///< empty when no vignette is known
};

}  // namespace ldsm
