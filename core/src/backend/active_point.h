// A point in the optimisation window: inverse depth in its host keyframe, the host's pattern
// intensities, and one photometric residual per other keyframe of the window.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "model/patch_point.h"
#include "model/residual_pattern.h"

namespace ldsm {

class WindowKeyframe;

enum class ResidualState : std::uint8_t { Inlier, Outlier, OutOfBounds };

struct PointResidual {
  WindowKeyframe* target = nullptr;
  ResidualState state = ResidualState::Inlier;
  float energy = 0.f;  ///< weighted Huber energy of the pattern at the last evaluation
  Eigen::Vector2f projection =
      Eigen::Vector2f::Zero();  ///< centre pixel in the target at the last evaluation
};

/// Smallest inverse depth a point's optimisation may reach (the initialisation scales the first
/// map's depths to about 1). A point that runs off to infinity loses up to three quarters of its
/// inverse depth per step; without a floor it underflowed, and its Jacobians (its camera
/// coordinates are its ray divided by the inverse depth) overflowed float and made the whole
/// window's system NaN (found with a focal and principal point correction on kitti00_200).
constexpr float kMinInverseDepth = 1e-10f;

struct ActivePoint {
  std::uint64_t id = 0;
  WindowKeyframe* host = nullptr;
  float u = 0.f, v = 0.f;  ///< level-0 pixel in the host
  float idepth = 1.f;
  float idepth_backup = 1.f;
  bool is_corner = false;
  /// A point of a reactivated map keyframe: its depth is the map's and stays fixed; its
  /// residuals constrain the active keyframes only.
  bool fixed = false;
  /// For a fixed point: an inlier in the newest keyframe at the last optimisation (or a point of
  /// the keyframe relocalisation found the frame in). Only verified map points guide tracking.
  bool verified = false;
  float colors[kPatternSize] = {};        ///< host intensities of the pattern
  float grad_weights[kPatternSize] = {};  ///< c^2 / (c^2 + |grad I_host|^2) per pattern pixel
  std::vector<PointResidual> residuals;

  // Filled by the last linearisation (Schur complement on the inverse depth).
  float hessian_idepth = 0.f;  ///< J_d^T W J_d summed over inlier residuals
  float gradient_idepth = 0.f;
  int inlier_residuals = 0;
};

}  // namespace ldsm

namespace ldsm {

/// Fills `point` for host pixel (u, v): pattern intensities and gradient weights from the host's
/// level 0 (gradient weight constant c). Returns false when the pattern leaves the image.
/// The point as the map keeps it once it left the window.
PatchPoint toPatchPoint(const ActivePoint& point);
/// A fixed point hosted by a reactivated map keyframe.
void fromPatchPoint(const PatchPoint& patch, WindowKeyframe& host, ActivePoint& point);

bool initActivePoint(ActivePoint& point, WindowKeyframe& host, float u, float v, float idepth,
                     float gradient_weight_c);

}  // namespace ldsm
