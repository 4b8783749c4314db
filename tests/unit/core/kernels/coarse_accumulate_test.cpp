// The coarse tracker's normal equations: the SIMD kernel (selected instruction set and plain C++)
// and the scalar reference against double sums of coarseJacobianRow, on random residuals of
// every tail length. Tolerance: relative 1e-5 of the magnitude, the Cauchy-Schwarz bound
// sqrt(H_ii H_jj) (sqrt(H_ii sum w r^2) for g) of the sum of the terms' absolute values.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "frontend/coarse_residuals.h"
#include "kernels/coarse_accumulate.h"

namespace ldsm {
namespace {

constexpr double kTol = 1e-5;

WarpedResiduals randomResiduals(int n, std::mt19937& rng) {
  std::uniform_real_distribution<float> U(-1.f, 1.f);
  WarpedResiduals w;
  w.allocate(static_cast<std::size_t>(n) + 5);
  for (int i = 0; i < n + 5; ++i) {  // entries past count must be ignored
    w.dx_fx[i] = 20000.f * U(rng);
    w.dy_fy[i] = 20000.f * U(rng);
    w.nx[i] = 0.7f * U(rng);
    w.ny[i] = 0.5f * U(rng);
    w.iz[i] = 0.3f + 0.25f * U(rng);
    w.ref_term[i] = 120.f + 100.f * U(rng);
    w.residual[i] = 15.f * U(rng);
    w.weight[i] = 0.5f + 0.5f * U(rng);
  }
  w.count = n;
  return w;
}

struct Oracle {
  CoarseMatrix H = CoarseMatrix::Zero();
  CoarseVector g = CoarseVector::Zero();
  double wr2 = 0.0;
};

Oracle oracle(const WarpedResiduals& w) {
  Oracle o;
  for (int i = 0; i < w.count; ++i) {
    float J[kCoarseParams];
    coarseJacobianRow(w.dx_fx[i], w.dy_fy[i], w.nx[i], w.ny[i], w.iz[i], w.ref_term[i], J);
    const Eigen::Map<const Eigen::Matrix<float, kCoarseParams, 1>> Jm(J);
    const Eigen::Matrix<double, kCoarseParams, 1> Jd = Jm.cast<double>();
    o.H += w.weight[i] * Jd * Jd.transpose();
    o.g += static_cast<double>(w.weight[i]) * w.residual[i] * Jd;
    o.wr2 += static_cast<double>(w.weight[i]) * w.residual[i] * w.residual[i];
  }
  return o;
}

void expectNear(const CoarseMatrix& H, const CoarseVector& g, const Oracle& o, const char* what,
                int n) {
  for (int i = 0; i < kCoarseParams; ++i) {
    for (int j = 0; j < kCoarseParams; ++j)
      ASSERT_NEAR(H(i, j), o.H(i, j), kTol * std::sqrt(o.H(i, i) * o.H(j, j)) + 1e-12)
          << what << " n=" << n << " (" << i << "," << j << ")";
    ASSERT_NEAR(g(i), o.g(i), kTol * std::sqrt(o.H(i, i) * o.wr2) + 1e-12)
        << what << " n=" << n << " " << i;
  }
}

void kernel(const WarpedResiduals& w, CoarseMatrix& H, CoarseVector& g) {
  simd::CoarseResidualArrays a;
  a.dx_fx = w.dx_fx.data();
  a.dy_fy = w.dy_fy.data();
  a.nx = w.nx.data();
  a.ny = w.ny.data();
  a.iz = w.iz.data();
  a.ref_term = w.ref_term.data();
  a.residual = w.residual.data();
  a.weight = w.weight.data();
  a.count = w.count;
  double sums[simd::kCoarseSums];
  simd::accumulateCoarseSystem<simd::Vec4Scalar>(a, sums);
  for (int i = 0; i < kCoarseParams; ++i) {
    g(i) = sums[simd::kCoarseUpper + i];
    for (int j = i; j < kCoarseParams; ++j) H(i, j) = H(j, i) = sums[simd::coarseUpperIndex(i, j)];
  }
}

TEST(CoarseAccumulate, KernelsMatchDoubleSums) {
  std::mt19937 rng(9);
  for (int n : {0, 1, 2, 3, 4, 5, 7, 255, 256, 257, 259, 1000, 4099}) {
    const WarpedResiduals w = randomResiduals(n, rng);
    const Oracle o = oracle(w);
    CoarseMatrix H;
    CoarseVector g;
    accumulateNormalEquations(w, H, g);
    expectNear(H, g, o, simd::kSimdName, n);
    kernel(w, H, g);
    expectNear(H, g, o, "plain C++ vector", n);
    reference::accumulateNormalEquations(w, H, g);
    expectNear(H, g, o, "scalar reference", n);
    if (n == 0) {
      accumulateNormalEquations(w, H, g);
      EXPECT_TRUE(H.isZero(0.0));
      EXPECT_TRUE(g.isZero(0.0));
    }
  }
}

TEST(CoarseAccumulate, SymmetricAndZeroWeightsIgnored) {
  std::mt19937 rng(4);
  WarpedResiduals w = randomResiduals(37, rng);
  w.dx_fx[5] = 1e18f;  // a zero-weight residual with huge values contributes nothing
  w.residual[5] = -1e18f;
  w.weight[5] = 0.f;
  CoarseMatrix H;
  CoarseVector g;
  accumulateNormalEquations(w, H, g);
  EXPECT_TRUE(H.isApprox(H.transpose(), 0.0));
  expectNear(H, g, oracle(w), "zero weight", 37);
}

}  // namespace
}  // namespace ldsm
