// Building blocks of the procedural textures: periodic value noise with precomputed lattices,
// fractal sums of it, and smooth steps. Everything is deterministic (integer hashing, IEEE
// arithmetic only).
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "ldsm/drivers/sim/det_math.h"

namespace ldsm::drivers::sim {

/// Quintic fade 6t^5 - 15t^4 + 10t^3 (C2 interpolation weight).
inline double fade(double t) {
  return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

inline double clamp01(double x) {
  return x < 0.0 ? 0.0 : (x > 1.0 ? 1.0 : x);
}

inline double smoothstep(double a, double b, double x) {
  const double t = clamp01((x - a) / (b - a));
  return t * t * (3.0 - 2.0 * t);
}

inline double lerp(double a, double b, double t) {
  return a + (b - a) * t;
}

/// Positive remainder of x modulo m (m > 0).
inline double wrapCoord(double x, double m) {
  return x - std::floor(x / m) * m;
}

/// Value noise in [0, 1) on a lattice of period_x x period_y cells, repeating with that period.
class PeriodicNoise {
 public:
  PeriodicNoise(int period_x, int period_y, std::uint32_t seed)
      : px_(period_x), py_(period_y), lattice_(static_cast<std::size_t>(period_x) * period_y) {
    for (int y = 0; y < py_; ++y)
      for (int x = 0; x < px_; ++x)
        lattice_[static_cast<std::size_t>(y) * px_ + x] =
            hashUnit(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y), seed);
  }

  /// Noise at (x, y) in lattice cells.
  double at(double x, double y) const {
    const double fx = std::floor(x), fy = std::floor(y);
    const double tx = fade(x - fx), ty = fade(y - fy);
    int ix = static_cast<int>(fx) % px_, iy = static_cast<int>(fy) % py_;
    if (ix < 0) ix += px_;
    if (iy < 0) iy += py_;
    const int ix1 = ix + 1 == px_ ? 0 : ix + 1, iy1 = iy + 1 == py_ ? 0 : iy + 1;
    const double a = lattice_[static_cast<std::size_t>(iy) * px_ + ix];
    const double b = lattice_[static_cast<std::size_t>(iy) * px_ + ix1];
    const double c = lattice_[static_cast<std::size_t>(iy1) * px_ + ix];
    const double d = lattice_[static_cast<std::size_t>(iy1) * px_ + ix1];
    return lerp(lerp(a, b, tx), lerp(c, d, tx), ty);
  }

 private:
  int px_, py_;
  std::vector<double> lattice_;
};

/// Fractal sum of periodic noise over a square of `size` texels: octave k has
/// base_cells * 2^k cells across and amplitude gain^k; normalised to [0, 1).
class FractalNoise {
 public:
  FractalNoise(int size, int base_cells_x, int base_cells_y, int octaves, double gain,
               std::uint32_t seed) {
    double amp = 1.0;
    for (int k = 0; k < octaves; ++k) {
      const int cx = base_cells_x << k, cy = base_cells_y << k;
      octaves_.emplace_back(cx, cy, hash32(seed, static_cast<std::uint32_t>(k)));
      scale_x_.push_back(static_cast<double>(cx) / size);
      scale_y_.push_back(static_cast<double>(cy) / size);
      amp_.push_back(amp);
      total_ += amp;
      amp *= gain;
    }
  }

  /// Value at texel coordinates (x, y) of the repeating square.
  double at(double x, double y) const {
    double sum = 0.0;
    for (std::size_t k = 0; k < octaves_.size(); ++k)
      sum += amp_[k] * octaves_[k].at(x * scale_x_[k], y * scale_y_[k]);
    return sum / total_;
  }

 private:
  std::vector<PeriodicNoise> octaves_;
  std::vector<double> scale_x_, scale_y_, amp_;
  double total_ = 0.0;
};

}  // namespace ldsm::drivers::sim
