// Photometric camera model I = G(t * V(x) * B(x)) (Engel et al., TUM-Mono): G the camera
// response, t the exposure time, V the vignette and B the scene irradiance. PhotometricModel
// applies it in both directions on raw (not yet rectified) input images.
#pragma once

#include <array>
#include <cstdint>

#include "ldsm/camera/calibration.h"
#include "ldsm/image.h"

namespace ldsm {

/// Throws ldsm::InputError unless the calibration is usable for images of width x height: the
/// inverse response (when present) finite, non-decreasing and not constant (the message names
/// the first bad index); the vignette (when present) of size width x height with every value in
/// (0, 1] (the message names the first bad pixel).
void validatePhotometricCalibration(const PhotometricCalibration& calibration, int width,
                                    int height);

class PhotometricModel {
 public:
  /// Validates `calibration` (see above). As in DSO, the inverse response is normalized to map
  /// 0 -> 0 and 255 -> 255 (an affine change of irradiance units); without a response it is the
  /// identity, without a vignette V = 1.
  PhotometricModel(const PhotometricCalibration& calibration, int width, int height);

  int width() const { return width_; }
  int height() const { return height_; }

  /// Irradiance B = G^-1(I) / V / exposure of an 8-bit image of the model's size into `out`
  /// (resized; no allocation when its capacity suffices). `exposure` must be finite and > 0 (pass
  /// 1 when unknown). Throws ldsm::InputError on a wrong image size or exposure.
  void correct(ImageView<const std::uint8_t> in, ImageF& out, float exposure = 1.0f) const;

  /// The forward direction: I = G(exposure * V * B), rounded to the nearest 8-bit value and
  /// clamped to [0, 255]. Same size and exposure rules as correct().
  void render(ImageView<const float> irradiance, ImageU8& out, float exposure = 1.0f) const;

  /// G^-1(v), normalized.
  float inverseResponse(std::uint8_t v) const { return inverse_response_[v]; }
  const std::array<float, 256>& inverseResponseTable() const { return inverse_response_; }

  /// G(energy): the continuous pixel value in [0, 255] whose inverse response is `energy`
  /// (piecewise linear between table entries, clamped outside the table's range).
  float response(float energy) const;

  bool hasVignette() const { return !vignette_.empty(); }
  /// V at input resolution (empty when there is none).
  const ImageF& vignette() const { return vignette_; }

 private:
  void checkArguments(int width, int height, float exposure, const char* what) const;

  int width_;
  int height_;
  std::array<float, 256> inverse_response_{};
  ImageF vignette_;
  ImageF inverse_vignette_;  ///< 1 / V, empty when there is no vignette
};

}  // namespace ldsm
