// Inverse camera response G^-1 from an exposure sweep of a static scene, as in the TUM-Mono
// calibration (Engel, Usenko, Cremers: "A Photometrically Calibrated Benchmark For Monocular
// Visual Odometry", 2016). With I_ix = G(t_i B_x) for image i of exposure t_i and scene
// irradiance B_x at pixel x, U = G^-1 and B are found by alternating the least-squares updates
//   B_x  = sum_i t_i U(I_ix) / sum_i t_i^2
//   U(k) = mean of t_i B_x over the observations with I_ix = k
// over the observations that are neither dark nor saturated; then observations whose grey value
// is far from what the fit predicts are dropped and the fit repeated. U is fixed up to scale: the
// result is scaled to U(255) = 255 (DSO's convention; values above the observed range are
// extrapolated, so this scale is the least accurate part, which does not matter to the engine).
//
// Checks: images mostly saturated or dark are skipped; brightness must follow exposure (it does
// not when auto-exposure or auto-gain was on, or the exposure times are wrong: between each image
// and the first one exposed at least 1.5x longer, the median change of the pixels in range must
// be positive); the raw estimate is checked for monotonicity (reported), and the written curve is
// its closest non-decreasing fit.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "ldsm/calib/exposed_image.h"

namespace ldsm::calib {

struct ResponseCalibrationOptions {
  /// Darker pixel values are not used, nor a pixel's values in exposures up to the longest one in
  /// which it was at most min_value - 4 (black clipping that noise pulled up).
  int min_value = 5;
  /// Brighter pixel values count as saturated, and so do a pixel's values in the exposures from
  /// the first one in which it was at least max_value + 4: clipped pixels that noise pulled
  /// below 255 would otherwise corrupt the top of the curve. Keep a margin of a few noise sigmas
  /// below the value at which the camera clips.
  int max_value = 250;
  int max_iterations = 200;
  double tolerance = 1e-6;        ///< stop when no U(k) changes by more than this (relative)
  int max_pixels = 100000;        ///< pixels per image used at most (a regular subsample)
  double min_exposure_range = 8;  ///< longest / shortest usable exposure, at least
  /// Images with a smaller fraction of pixels in [min_value, max_value] are skipped.
  double min_usable_fraction = 0.05;
  /// Make a failed brightness check a warning instead of an error (see calibrateResponse).
  bool allow_inconsistent = false;
  /// Warn about images whose fitted exposure differs from the given one by more than this.
  double max_exposure_deviation = 0.1;
};

struct ResponseCalibrationResult {
  /// G^-1 for pcalib.txt: non-decreasing, scaled so that entry 255 is 255.
  std::array<float, 256> inverse_response{};
  /// The raw estimate per pixel value on the same scale, NaN where the value was not observed.
  std::array<double, 256> estimate{};
  /// Observations per pixel value used in the estimate.
  std::array<std::int64_t, 256> counts{};
  int first_observed = 0;  ///< smallest and largest pixel values with an estimate
  int last_observed = 0;
  /// Pixel values v whose raw estimate is below the estimate of the value before them.
  std::vector<int> non_monotonic;
  double rms_residual = 0.0;  ///< RMS of U(I) - t B over the observations (scale of U)
  /// Robust spread (grey levels) of the values around the fit; samples beyond 4 of it (at least
  /// 2 levels) are not used: clipped values that noise moved into range.
  double noise_sigma = 0.0;
  /// Per input image: fitted / given exposure time (NaN for skipped images).
  std::vector<double> exposure_scale;
  int images_used = 0;
  /// Images skipped because almost all their pixels are saturated, or dark (normal at the ends
  /// of a sweep).
  std::vector<std::string> skipped_saturated, skipped_dark;
  int iterations = 0;
  std::vector<std::string> warnings;
};

/// Recovers G^-1 from `images` (all the same size, each with its exposure time). `source` names
/// the sweep in messages. Throws ldsm::InputError "<source>: ..." saying what to do when: an
/// image is empty or of another size, an exposure time is not positive and finite, fewer than 3
/// images have usable pixels (naming how many are saturated or dark), the usable exposures span
/// less than min_exposure_range, the pixel values span less than 64 grey levels, or brightness
/// does not follow exposure (auto-exposure / auto-gain on, or wrong exposure times) unless
/// allow_inconsistent is set.
ResponseCalibrationResult calibrateResponse(const std::vector<ExposedImage>& images,
                                            const ResponseCalibrationOptions& options,
                                            const std::string& source);

/// The closest non-decreasing sequence to `values` in weighted least squares (pool adjacent
/// violators); entries with weight 0 are ignored and returned unchanged.
std::vector<double> monotoneFit(const std::vector<double>& values,
                                const std::vector<double>& weights);

}  // namespace ldsm::calib
