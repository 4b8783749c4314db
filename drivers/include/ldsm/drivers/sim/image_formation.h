// Image formation of the synthetic camera: irradiance B -> times exposure time t -> times
// vignette V(x) -> response G -> + Gaussian-like noise -> 8-bit rounding:
//   I(x) = round(255 G(B(x) V(x) t / kSaturationExposureMs) + sigma n(x)), clamped to [0, 255].
// G comes from a 4097-entry table interpolated linearly; the noise n has unit variance and is the
// centred, scaled sum of four uniform bytes of an integer hash of (pixel, frame key), so it is
// reproducible and identical on every platform.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "ldsm/camera/calibration.h"
#include "ldsm/drivers/sim/sim_options.h"
#include "ldsm/image.h"

namespace ldsm::drivers::sim {

/// Exposure time (ms) at which irradiance 1 (times vignette 1) reaches the top of the response.
inline constexpr double kSaturationExposureMs = 20.0;

class ImageFormation {
 public:
  /// Response, vignette and noise from `options` for images of `camera`'s size (vignette centred
  /// on the principal point, 1 - options.vignette at the farthest corner).
  ImageFormation(const SimOptions& options, const PinholeIntrinsics& camera);

  /// Forms the 8-bit image of `irradiance` (camera size) exposed for `exposure_ms`. `noise_key`
  /// selects the noise pattern (use a different key per frame). Throws ldsm::InputError on a
  /// wrongly sized irradiance image.
  void apply(const ImageF& irradiance, double exposure_ms, std::uint32_t noise_key,
             ImageU8& out) const;

  /// G(e) * 255 for normalised exposure e (the table used by apply, before noise and rounding).
  double responseGrey(double e) const;
  /// G^-1(v) * 255 for v = 0..255 (inverse of responseGrey), as a DSO pcalib.txt expects.
  const std::array<float, 256>& inverseResponse() const { return inverse_response_; }
  /// V(x) in (0, 1] at every pixel.
  const ImageF& vignette() const { return vignette_; }
  double noiseSigma() const { return sigma_; }

 private:
  static constexpr int kTableSize = 4096;
  std::vector<float> table_;  // kTableSize + 1 entries of G * 255
  std::array<float, 256> inverse_response_{};
  ImageF vignette_;
  double sigma_ = 0.0;
};

/// The analytic response curve G(e) in [0, 1] for e in [0, 1] (deterministic pow).
double responseCurve(SimResponse response, double e);

/// Exposure time (ms) at time t (s): options.exposure_ms, or with exposure_changes a smooth
/// schedule exposure_ms * 2^(0.6 sin(2 pi t / 13 s) + 0.4 sin(2 pi t / 5.9 s + 1.3)), which stays
/// within [exposure_ms / 2, 2 exposure_ms].
double simExposureMs(const SimOptions& options, double t);

}  // namespace ldsm::drivers::sim
