// Options of the synthetic scene renderer: image size, frame rate, camera, image formation.
#pragma once

#include <cstdint>
#include <string>

namespace ldsm::drivers::sim {

/// Camera response curve G applied to normalised exposure e in [0, 1] (saturating above 1).
enum class SimResponse {
  Linear,  ///< G(e) = e
  Gamma,   ///< G(e) = e^(1/2.2)
  SCurve,  ///< gamma-like lift followed by a contrast S-curve: G(e) = s(e^0.6), s = smoothstep mix
};

/// "linear", "gamma", "scurve".
std::string toString(SimResponse response);
/// Inverse of toString; throws ldsm::ConfigError listing the valid names.
SimResponse parseSimResponse(const std::string& name);

struct SimOptions {
  int width = 640;
  int height = 480;
  double fps = 30.0;
  /// Focal length in pixels (fx = fy). 0: derived from hfov_deg.
  double focal_px = 0.0;
  /// Horizontal field of view in degrees, used when focal_px is 0.
  double hfov_deg = 80.0;
  /// Number of frames (at most 1e6); 0 uses the scene's default length.
  std::int64_t frames = 0;
  /// Nominal exposure time (ms). Irradiance 1 saturates the sensor at 20 ms (times vignette).
  double exposure_ms = 10.0;
  /// Smoothly varying exposure time (between about half and twice exposure_ms).
  bool exposure_changes = false;
  /// Vignette strength in [0, 0.9]: V = 1 at the principal point, 1 - vignette at the corners.
  double vignette = 0.3;
  SimResponse response = SimResponse::Gamma;
  /// Standard deviation of the additive noise in grey levels (0: none).
  double noise_sigma = 1.0;
  /// Seed of the noise.
  std::uint32_t seed = 1;
  /// Full-frame supersampling factor per axis (1: one sample per pixel plus edge anti-aliasing).
  int supersampling = 1;
  /// Anti-alias geometric edges (occlusion boundaries, corners) with 4 sub-samples per edge pixel.
  bool antialias_edges = true;
  /// Motion blur: number of sub-frame poses averaged over the exposure time (1: none).
  int motion_blur_samples = 1;
};

/// Throws ldsm::ConfigError naming the first option outside its range.
void validate(const SimOptions& options);

/// Focal length in pixels that `options` describe (focal_px, or from hfov_deg and width).
double focalLengthPx(const SimOptions& options);

}  // namespace ldsm::drivers::sim
