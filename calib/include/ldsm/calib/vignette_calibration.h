// Vignette V(x) from images of a flat, evenly lit, uniformly coloured surface with a known
// response: each image's irradiance G^-1(I) / t is normalised by its median and the images are
// averaged; a smooth radial model
//   V(x) = 1 + a r^2 + b r^4 + c r^6,  r = |x - centre| / (half the image diagonal)
// is fitted to the average by robust (Huber-weighted) Levenberg-Marquardt, the centre fitted or
// given, and scaled to a maximum of 1 over the image.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ldsm/calib/exposed_image.h"
#include "ldsm/image.h"

namespace ldsm::calib {

struct VignetteCalibrationOptions {
  int min_value = 5;    ///< darker pixel values are not used
  int max_value = 250;  ///< brighter pixel values are not used (near saturation)
  /// The vignette centre in pixels; nullopt: fitted (starting at the image centre).
  std::optional<Eigen::Vector2d> centre;
  int block = 8;  ///< the average is fitted on blocks of block x block pixels
  /// Residuals beyond this many robust standard deviations get down-weighted (Huber).
  double huber_k = 2.0;
  /// Warn when the relative RMS of the fit (inliers) exceeds this.
  double max_fit_rms = 0.02;
};

struct VignetteCalibrationResult {
  ImageF vignette;  ///< the model at every pixel, maximum 1 (what vignette.png gets)
  /// The measured average (each image normalised, then scaled like the model), NaN where no
  /// image had a usable value.
  ImageF measured;
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  std::array<double, 3> coefficients{};  ///< a, b, c of the model before scaling to max 1
  double radius_px = 0.0;                ///< the r = 1 radius: half the image diagonal
  double scale = 1.0;                    ///< V = scale * (1 + a r^2 + b r^4 + c r^6)
  double fit_rms = 0.0;                  ///< relative RMS residual of the blocks (Huber inliers)
  double outlier_fraction = 0.0;         ///< blocks down-weighted by the robust fit
  double min_value = 0.0;                ///< smallest V over the image
  int images_used = 0;
  std::vector<std::string> warnings;
};

/// Fits the vignette to `images` (same size, exposure times > 0) with the inverse response
/// `inverse_response` (pcalib.txt). `source` names the image set in messages. Throws
/// ldsm::InputError "<source>: ..." saying what to do when: there is no image, an image is
/// empty or of another size, an exposure time is not positive and finite, the response is not
/// increasing, no image has enough usable pixels (too dark or saturated), or the usable pixels do
/// not cover enough of the image for a fit.
VignetteCalibrationResult calibrateVignette(const std::vector<ExposedImage>& images,
                                            const std::array<float, 256>& inverse_response,
                                            const VignetteCalibrationOptions& options,
                                            const std::string& source);

}  // namespace ldsm::calib
