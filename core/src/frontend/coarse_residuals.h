// The coarse tracker's photometric residuals, linearised per point and stored as a struct of
// arrays, and the accumulation of their normal equations (vectorised over the points).
//
// Residual of a reference point p (pixel (x, y), inverse depth d) for the parameters
// T = T_frame_ref (SE3, left-perturbed: T <- exp(delta) T) and the frame's affine (a, b):
//   r = I_frame[pi(T p)] - (s (I_ref[p] - b_ref) + b),   s = exp(a - a_ref) e_frame / e_ref.
// Parameter order: [rho (3), phi (3), a, b], the SE3 tangent order of ldsm.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <vector>

namespace ldsm {

constexpr int kCoarseParams = 8;
using CoarseMatrix = Eigen::Matrix<double, kCoarseParams, kCoarseParams>;
using CoarseVector = Eigen::Matrix<double, kCoarseParams, 1>;

/// Residuals of the points that project into the frame, with what their Jacobians need.
struct WarpedResiduals {
  std::vector<float> dx_fx;     ///< frame gradient dI/du times fx (of the level)
  std::vector<float> dy_fy;     ///< frame gradient dI/dv times fy
  std::vector<float> nx;        ///< normalised image coordinate X/Z in the frame
  std::vector<float> ny;        ///< Y/Z
  std::vector<float> iz;        ///< inverse depth 1/Z in the frame
  std::vector<float> ref_term;  ///< s (I_ref - b_ref): minus the derivative w.r.t. a
  std::vector<float> residual;  ///< r
  std::vector<float> weight;    ///< robust (Huber) times gradient-dependent weight
  int count = 0;

  /// Sizes every array for n points (done when the tracking reference changes, never per frame).
  void allocate(std::size_t n);
};

/// The row dr/d[rho, phi, a, b] of one residual.
inline void coarseJacobianRow(float dx_fx, float dy_fy, float nx, float ny, float iz,
                              float ref_term, float J[kCoarseParams]) {
  J[0] = dx_fx * iz;
  J[1] = dy_fy * iz;
  J[2] = -iz * (dx_fx * nx + dy_fy * ny);
  J[3] = -dx_fx * nx * ny - dy_fy * (1.f + ny * ny);
  J[4] = dx_fx * (1.f + nx * nx) + dy_fy * nx * ny;
  J[5] = dy_fy * nx - dx_fx * ny;
  J[6] = -ref_term;
  J[7] = -1.f;
}

/// H = sum w J^T J and g = sum w J^T r over the buffer (SIMD kernel of
/// kernels/coarse_accumulate.h: float lane sums in blocks, summed in double).
void accumulateNormalEquations(const WarpedResiduals& residuals, CoarseMatrix& H, CoarseVector& g);

namespace reference {
/// The scalar formulation of accumulateNormalEquations (one coarseJacobianRow per residual).
void accumulateNormalEquations(const WarpedResiduals& residuals, CoarseMatrix& H, CoarseVector& g);
}  // namespace reference

}  // namespace ldsm
