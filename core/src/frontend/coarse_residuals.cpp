#include "frontend/coarse_residuals.h"

#include <algorithm>

#include "kernels/coarse_accumulate.h"

namespace ldsm {

static_assert(kCoarseParams == simd::kCoarseRow, "the kernel's row is the tracker's parameters");

void WarpedResiduals::allocate(std::size_t n) {
  for (std::vector<float>* v : {&dx_fx, &dy_fy, &nx, &ny, &iz, &ref_term, &residual, &weight}) {
    v->assign(n, 0.f);
  }
  count = 0;
}

void accumulateNormalEquations(const WarpedResiduals& residuals, CoarseMatrix& H, CoarseVector& g) {
  simd::CoarseResidualArrays a;
  a.dx_fx = residuals.dx_fx.data();
  a.dy_fy = residuals.dy_fy.data();
  a.nx = residuals.nx.data();
  a.ny = residuals.ny.data();
  a.iz = residuals.iz.data();
  a.ref_term = residuals.ref_term.data();
  a.residual = residuals.residual.data();
  a.weight = residuals.weight.data();
  a.count = residuals.count;
  double sums[simd::kCoarseSums];
  simd::accumulateCoarseSystem<simd::Vec4>(a, sums);
  for (int i = 0; i < kCoarseParams; ++i) {
    g(i) = sums[simd::kCoarseUpper + i];
    for (int j = i; j < kCoarseParams; ++j) H(i, j) = H(j, i) = sums[simd::coarseUpperIndex(i, j)];
  }
}

namespace reference {

void accumulateNormalEquations(const WarpedResiduals& residuals, CoarseMatrix& H, CoarseVector& g) {
  constexpr int kBlock = 256;  // float partial sums stay accurate over this many points
  using Vector8f = Eigen::Matrix<float, kCoarseParams, 1>;
  using Matrix8f = Eigen::Matrix<float, kCoarseParams, kCoarseParams>;
  H.setZero();
  g.setZero();
  const float* dx_fx = residuals.dx_fx.data();
  const float* dy_fy = residuals.dy_fy.data();
  const float* nx = residuals.nx.data();
  const float* ny = residuals.ny.data();
  const float* iz = residuals.iz.data();
  const float* ref_term = residuals.ref_term.data();
  const float* r = residuals.residual.data();
  const float* w = residuals.weight.data();
  for (int begin = 0; begin < residuals.count; begin += kBlock) {
    const int end = std::min(begin + kBlock, residuals.count);
    Matrix8f h = Matrix8f::Zero();
    Vector8f b = Vector8f::Zero();
    for (int i = begin; i < end; ++i) {
      Vector8f J;
      coarseJacobianRow(dx_fx[i], dy_fy[i], nx[i], ny[i], iz[i], ref_term[i], J.data());
      // A full rank-1 update: 8 x 8 floats vectorise better than the triangle.
      h.noalias() += (w[i] * J) * J.transpose();
      b.noalias() += (w[i] * r[i]) * J;
    }
    H += h.cast<double>();
    g += b.cast<double>();
  }
  // (w J_i) J_j and (w J_j) J_i round differently: make H exactly symmetric.
  for (int row = 1; row < kCoarseParams; ++row) {
    for (int col = 0; col < row; ++col) H(row, col) = H(col, row);
  }
}

}  // namespace reference
}  // namespace ldsm
