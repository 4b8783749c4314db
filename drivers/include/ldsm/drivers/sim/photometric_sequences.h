// Synthetic data for the photometric calibration tools, formed by the simulator's ImageFormation
// (known response, vignette, noise): exposure sweeps of a static scene and images of a flat,
// evenly lit surface; and writing them as a TUM-Mono style folder (images/ + times.txt).
#pragma once

#include <string>
#include <vector>

#include "ldsm/camera/calibration.h"
#include "ldsm/drivers/sim/sim_options.h"
#include "ldsm/image.h"

namespace ldsm::drivers::sim {

/// Images with the exposure times they report, and the photometric calibration that formed them.
struct ExposedFrames {
  std::vector<ImageU8> images;
  std::vector<double> exposures_ms;  ///< as reported (times.txt)
  PhotometricCalibration truth;      ///< inverse response (G^-1 * 255) and vignette used
};

/// `count` exposure times from min_ms to max_ms, evenly spaced in log scale. Throws
/// ldsm::ConfigError unless 0 < min_ms < max_ms and count >= 2.
std::vector<double> exposureSweepTimes(double min_ms, double max_ms, int count);

/// A static view of built-in scene `scene` (from its first pose) exposed at each of
/// `exposures_ms`, with the response, vignette, noise and size of `options` (its exposure
/// settings are ignored). `formed_exposures_ms`, when not empty (same count), are the exposures
/// the images are really formed with while `exposures_ms` are reported: a camera with auto-gain,
/// or wrong exposure times. Throws like SimSource and ldsm::ConfigError on a count mismatch.
ExposedFrames renderExposureSweep(const std::string& scene, const SimOptions& options,
                                  const std::vector<double>& exposures_ms,
                                  const std::vector<double>& formed_exposures_ms = {});

/// A flat, evenly lit surface of irradiance `irradiance` (1 saturates at 20 ms without vignette)
/// filling the view, exposed at each of `exposures_ms`, with the response, vignette (centred on
/// the principal point of `options`' camera) and noise of `options`. A non-zero `spot` darkens a
/// disc a quarter of the image height across, centred at a quarter of the
/// width and height, by that fraction (a stain on the surface).
ExposedFrames renderFlatField(const SimOptions& options, double irradiance,
                              const std::vector<double>& exposures_ms, double spot = 0.0);

/// Writes out_dir/images/00000.png ... and out_dir/times.txt ("id timestamp exposure_ms", frames
/// 0.1 s apart), creating out_dir. Throws ldsm::Error naming a file that cannot be written.
void writeExposedFrames(const std::string& out_dir, const std::vector<ImageU8>& images,
                        const std::vector<double>& exposures_ms);

}  // namespace ldsm::drivers::sim
