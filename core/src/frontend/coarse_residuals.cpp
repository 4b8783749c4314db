#include "frontend/coarse_residuals.h"

#include <algorithm>

namespace ldsm {

void WarpedResiduals::allocate(std::size_t n) {
  for (std::vector<float>* v : {&dx_fx, &dy_fy, &nx, &ny, &iz, &ref_term, &residual, &weight}) {
    v->assign(n, 0.f);
  }
  count = 0;
}

void accumulateNormalEquations(const WarpedResiduals& residuals, CoarseMatrix& H, CoarseVector& g) {
  constexpr int kBlock = 256;  // float partial sums stay accurate over this many points
  constexpr int kUpper = kCoarseParams * (kCoarseParams + 1) / 2;
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
    float h[kUpper] = {};
    float b[kCoarseParams] = {};
    for (int i = begin; i < end; ++i) {
      float J[kCoarseParams];
      coarseJacobianRow(dx_fx[i], dy_fy[i], nx[i], ny[i], iz[i], ref_term[i], J);
      const float wi = w[i];
      const float wr = wi * r[i];
      int k = 0;
      for (int row = 0; row < kCoarseParams; ++row) {
        const float wj = wi * J[row];
        b[row] += J[row] * wr;
        for (int col = row; col < kCoarseParams; ++col) h[k++] += wj * J[col];
      }
    }
    int k = 0;
    for (int row = 0; row < kCoarseParams; ++row) {
      g(row) += b[row];
      for (int col = row; col < kCoarseParams; ++col) H(row, col) += h[k++];
    }
  }
  H.triangularView<Eigen::StrictlyLower>() = H.transpose();
}

}  // namespace ldsm
