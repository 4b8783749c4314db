#include "response_solver.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ldsm::calib::detail {

ResponseSolver::ResponseSolver(const SweepSamples& sweep)
    : sweep_(sweep),
      use_(static_cast<std::size_t>(sweep.imageCount()) * sweep.pixelCount()),
      B_(sweep.pixelCount(), std::numeric_limits<double>::quiet_NaN()) {
  for (int i = 0; i < sweep.imageCount(); ++i)
    for (std::size_t x = 0; x < sweep.pixelCount(); ++x)
      use_[static_cast<std::size_t>(i) * sweep.pixelCount() + x] = sweep.valid(i, x);
  for (int k = 0; k < 256; ++k) U_[static_cast<std::size_t>(k)] = k;
}

int ResponseSolver::solve(int max_iterations, double tolerance) {
  const int n_images = sweep_.imageCount();
  const std::size_t n_pixels = sweep_.pixelCount();
  std::array<double, 256> sum{};
  int iteration = 0;
  while (iteration < max_iterations) {
    ++iteration;
    for (std::size_t x = 0; x < n_pixels; ++x) {
      double num = 0.0, den = 0.0;
      int n = 0;
      for (int i = 0; i < n_images; ++i) {
        if (!used(i, x)) continue;
        const double t = sweep_.exposure(i);
        num += t * U_[sweep_.value(i, x)];
        den += t * t;
        ++n;
      }
      B_[x] = n >= 2 ? num / den : std::numeric_limits<double>::quiet_NaN();
    }
    sum.fill(0.0);
    count_.fill(0);
    for (int i = 0; i < n_images; ++i) {
      const double t = sweep_.exposure(i);
      for (std::size_t x = 0; x < n_pixels; ++x) {
        if (!used(i, x) || std::isnan(B_[x])) continue;
        sum[sweep_.value(i, x)] += t * B_[x];
        ++count_[sweep_.value(i, x)];
      }
    }
    // U is defined up to scale: the brightest well-observed value keeps its own value.
    int top = -1;
    for (int k = 255; k >= 0 && top < 0; --k)
      if (count_[static_cast<std::size_t>(k)] >= kMinResponseCount) top = k;
    if (top < 0) break;
    const auto t = static_cast<std::size_t>(top);
    const double scale = top / (sum[t] / static_cast<double>(count_[t]));
    double change = 0.0;
    for (std::size_t k = 0; k < 256; ++k) {
      if (count_[k] == 0) continue;
      const double u = scale * sum[k] / static_cast<double>(count_[k]);
      change = std::max(change, std::abs(u - U_[k]) / std::max(1.0, std::abs(u)));
      U_[k] = u;
    }
    if (change < tolerance) break;
  }
  return iteration;
}

std::size_t ResponseSolver::rejectOutliers(const std::array<double, 256>& curve, double k,
                                           double min_levels) {
  // Grey value whose G^-1 is e: inverse of the curve, extended linearly beyond both ends.
  const double top_slope = std::max((curve[255] - curve[247]) / 8.0, 1e-12);
  const double bottom_slope = std::max((curve[8] - curve[0]) / 8.0, 1e-12);
  auto greyOf = [&](double e) {
    if (e >= curve[255]) return 255.0 + (e - curve[255]) / top_slope;
    if (e <= curve[0]) return (e - curve[0]) / bottom_slope;
    const auto it = std::upper_bound(curve.begin(), curve.end(), e);
    const auto k1 = static_cast<std::size_t>(it - curve.begin()), k0 = k1 - 1;
    const double d = curve[k1] - curve[k0];
    return static_cast<double>(k0) + (d > 0 ? (e - curve[k0]) / d : 0.0);
  };
  const int n_images = sweep_.imageCount();
  const std::size_t n_pixels = sweep_.pixelCount();
  std::vector<float> offset(use_.size(), 0.0f);
  std::vector<float> magnitudes;
  for (int i = 0; i < n_images; ++i)
    for (std::size_t x = 0; x < n_pixels; ++x) {
      if (!used(i, x) || std::isnan(B_[x])) continue;
      const std::size_t s = static_cast<std::size_t>(i) * n_pixels + x;
      offset[s] = static_cast<float>(sweep_.value(i, x) - greyOf(sweep_.exposure(i) * B_[x]));
      magnitudes.push_back(std::abs(offset[s]));
    }
  if (magnitudes.empty()) return 0;
  const auto mid = magnitudes.begin() + static_cast<std::ptrdiff_t>(magnitudes.size() / 2);
  std::nth_element(magnitudes.begin(), mid, magnitudes.end());
  sigma_ = 1.4826 * *mid;
  const double limit = std::max(k * sigma_, min_levels);
  std::size_t dropped = 0;
  for (std::size_t s = 0; s < use_.size(); ++s)
    if (use_[s] && std::abs(offset[s]) > limit) {
      use_[s] = 0;
      ++dropped;
    }
  return dropped;
}

std::size_t ResponseSolver::restrictValues(int lo, int hi) {
  std::size_t dropped = 0;
  for (int i = 0; i < sweep_.imageCount(); ++i)
    for (std::size_t x = 0; x < sweep_.pixelCount(); ++x) {
      const std::size_t s = static_cast<std::size_t>(i) * sweep_.pixelCount() + x;
      const int v = sweep_.value(i, x);
      if (use_[s] && (v < lo || v > hi)) {
        use_[s] = 0;
        ++dropped;
      }
    }
  return dropped;
}

}  // namespace ldsm::calib::detail
