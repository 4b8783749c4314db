// Robust kernels rho(r) for iteratively reweighted least squares. Each kernel behaves like r^2 / 2
// near 0 and provides, for a residual r:
//   cost(r)       rho(r)
//   derivative(r) rho'(r)
//   weight(r)     rho'(r) / r, the IRLS weight (1 at r = 0), so that
//                 sum w_i r_i dr_i/dx = 0 is the normal equation of sum rho(r_i).
// S is float or double. All functions are inline and branch only on |r| versus the threshold k.
#pragma once

#include <cmath>
#include <string>

#include "ldsm/error.h"

namespace ldsm {

namespace detail {
template <typename S>
inline S checkedThreshold(S k, const char* kernel) {
  if (!(k > S(0)) || !std::isfinite(static_cast<double>(k))) {
    throw ConfigError(std::string(kernel) + " kernel: threshold must be finite and > 0 (got " +
                      std::to_string(static_cast<double>(k)) + ")");
  }
  return k;
}
}  // namespace detail

/// Plain least squares: rho(r) = r^2 / 2, weight 1.
template <typename S>
struct SquaredKernel {
  S cost(S r) const { return S(0.5) * r * r; }
  S derivative(S r) const { return r; }
  S weight(S /*r*/) const { return S(1); }
};

/// Huber: r^2 / 2 for |r| <= k, k (|r| - k/2) beyond (linear tails, convex).
template <typename S>
class HuberKernel {
 public:
  /// Throws ConfigError unless 0 < k < inf.
  explicit HuberKernel(S k) : k_(detail::checkedThreshold(k, "Huber")) {}
  S threshold() const { return k_; }

  S cost(S r) const {
    const S a = std::abs(r);
    return a <= k_ ? S(0.5) * r * r : k_ * (a - S(0.5) * k_);
  }
  S derivative(S r) const {
    if (std::abs(r) <= k_) return r;
    return r > S(0) ? k_ : -k_;
  }
  S weight(S r) const {
    const S a = std::abs(r);
    return a <= k_ ? S(1) : k_ / a;
  }

 private:
  S k_;
};

/// Cauchy (Lorentzian): k^2 / 2 log(1 + (r/k)^2); weight 1 / (1 + (r/k)^2). Never fully rejects.
template <typename S>
class CauchyKernel {
 public:
  /// Throws ConfigError unless 0 < k < inf.
  explicit CauchyKernel(S k) : k_(detail::checkedThreshold(k, "Cauchy")), inv_k2_(S(1) / (k * k)) {}
  S threshold() const { return k_; }

  S cost(S r) const { return S(0.5) * k_ * k_ * std::log1p(r * r * inv_k2_); }
  S derivative(S r) const { return r * weight(r); }
  S weight(S r) const { return S(1) / (S(1) + r * r * inv_k2_); }

 private:
  S k_;
  S inv_k2_;
};

/// Tukey biweight: k^2/6 (1 - (1 - (r/k)^2)^3) for |r| <= k, k^2/6 beyond; weight
/// (1 - (r/k)^2)^2 inside, 0 outside (outliers beyond k are rejected).
template <typename S>
class TukeyKernel {
 public:
  /// Throws ConfigError unless 0 < k < inf.
  explicit TukeyKernel(S k) : k_(detail::checkedThreshold(k, "Tukey")), inv_k2_(S(1) / (k * k)) {}
  S threshold() const { return k_; }

  S cost(S r) const {
    const S u = S(1) - r * r * inv_k2_;
    if (u <= S(0)) return k_ * k_ / S(6);
    return k_ * k_ / S(6) * (S(1) - u * u * u);
  }
  S derivative(S r) const { return r * weight(r); }
  S weight(S r) const {
    const S u = S(1) - r * r * inv_k2_;
    return u <= S(0) ? S(0) : u * u;
  }

 private:
  S k_;
  S inv_k2_;
};

}  // namespace ldsm
