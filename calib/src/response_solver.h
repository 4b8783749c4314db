// The least-squares core of the response calibration (private to calib/src): alternating updates
// of the inverse response U and the irradiance B over the valid samples of a sweep, and
// rejection of samples that the fit cannot explain (clipped values that noise moved into range).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "sweep_samples.h"

namespace ldsm::calib::detail {

/// Pixel values need this many observations for an estimate.
inline constexpr std::int64_t kMinResponseCount = 8;

class ResponseSolver {
 public:
  /// Starts from a linear response, U(k) = k, over the sweep's valid samples.
  explicit ResponseSolver(const SweepSamples& sweep);

  /// Alternates B_x = sum_i t_i U(I_ix) / sum_i t_i^2 (pixels with at least 2 samples) and
  /// U(k) = mean t_i B_x over the samples of value k until no U(k) changes by more than
  /// `tolerance` (relative). U is scaled so that the brightest well-observed value keeps its
  /// own value. Returns the number of iterations.
  int solve(int max_iterations, double tolerance);

  /// Predicts each used sample's grey value from `curve` (a non-decreasing G^-1 on the scale of
  /// U) and its t B, and stops using the samples off by more than max(k sigma, min_levels), sigma
  /// the robust (1.4826 MAD) spread of all offsets. Returns the number of samples dropped.
  std::size_t rejectOutliers(const std::array<double, 256>& curve, double k, double min_levels);

  /// Stops using the samples whose value is outside [lo, hi]. Returns the number dropped.
  std::size_t restrictValues(int lo, int hi);

  const std::array<double, 256>& inverseResponse() const { return U_; }
  const std::array<std::int64_t, 256>& counts() const { return count_; }
  /// B_x, NaN for pixels with fewer than 2 samples.
  const std::vector<double>& irradiance() const { return B_; }
  bool used(int i, std::size_t x) const {
    return use_[static_cast<std::size_t>(i) * sweep_.pixelCount() + x] != 0;
  }
  /// The robust spread of the grey-value offsets at the last rejectOutliers() (0 before).
  double noiseSigma() const { return sigma_; }

 private:
  const SweepSamples& sweep_;
  std::vector<std::uint8_t> use_;
  std::array<double, 256> U_{};
  std::array<std::int64_t, 256> count_{};
  std::vector<double> B_;
  double sigma_ = 0.0;
};

}  // namespace ldsm::calib::detail
