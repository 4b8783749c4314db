// Test access to the coarse initializer's internals (declared friend in coarse_initializer.h).
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "frontend/coarse_initializer.h"

namespace ldsm {

struct CoarseInitializerAccess {
  static std::vector<float>& idepth(CoarseInitializer& c, int level) {
    return c.levels_data_[level].idepth;
  }
  static std::vector<std::uint8_t>& good(CoarseInitializer& c, int level) {
    return c.levels_data_[level].good;
  }
  static const std::vector<Eigen::Vector2f>& pixels(const CoarseInitializer& c, int level) {
    return c.levels_data_[level].u;
  }
  static const std::vector<int>& parents(const CoarseInitializer& c, int level) {
    return c.levels_data_[level].parent;
  }
  static const std::array<int, CoarseInitializerSettings::kMaxNeighbours>& neighbours(
      const CoarseInitializer& c, int level, int index, int* count) {
    *count = c.levels_data_[level].neighbour_count[static_cast<std::size_t>(index)];
    return c.levels_data_[level].neighbours[static_cast<std::size_t>(index)];
  }
  static SE3d& pose(CoarseInitializer& c) { return c.T_; }
  static bool depthsDegenerate(CoarseInitializer& c) { return c.depthsDegenerate(); }
  static double parallax(const CoarseInitializer& c) { return c.rotationFreeParallax(); }

  /// Photometric energy over the points with mask[i] != 0 of level `level` against `frame`
  /// (exposure ratio 1) at (T, affine, d), without smoothness and priors; fills its gradient
  /// w.r.t. [rho, phi, a, b] (plus the affine prior's), the per-depth gradients (with the depth
  /// prior) and which points are inliers. Points outside the mask are made invalid (NaN depth).
  static double energy(CoarseInitializer& c, const ImagePyramid& frame, int level, const SE3d& T,
                       const AffineLight& affine, const std::vector<float>& d,
                       const std::vector<std::uint8_t>& mask, Eigen::Matrix<double, 8, 1>* b,
                       std::vector<float>* bd, std::vector<std::uint8_t>* inliers) {
    c.frame_ = &frame;
    c.exposure_ratio_ = 1.f;
    c.smoothness_weight_ = 0.f;
    std::vector<float> dm = d;
    for (std::size_t i = 0; i < d.size(); ++i) {
      if (!mask[i]) dm[i] = std::numeric_limits<float>::quiet_NaN();
    }
    std::vector<float> ir(d.size(), 1.f);
    std::vector<CoarseInitializer::PointLinearization> lin(d.size());
    std::vector<std::uint8_t> good(d.size());
    CoarseInitializer::Evaluation ev;
    c.evaluate(level, T, affine, dm.data(), ir.data(), lin.data(), good.data(), ev);
    c.frame_ = nullptr;
    if (b != nullptr) *b = ev.b;
    if (bd != nullptr) {
      bd->resize(d.size());
      for (std::size_t i = 0; i < d.size(); ++i) (*bd)[i] = lin[i].bd;
    }
    if (inliers != nullptr) *inliers = good;
    double e = 0;
    for (std::size_t i = 0; i < d.size(); ++i) {
      if (mask[i]) e += lin[i].energy;
    }
    return e;
  }
};

}  // namespace ldsm
