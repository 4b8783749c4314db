// The analytic Jacobians of the Sim(3) pose-graph edge against central differences of the
// residual under left perturbations exp(d) * S_w, from tiny to large residuals.
#include <gtest/gtest.h>

#include <random>

#include "loop/sim3_edge.h"

namespace ldsm::loop {
namespace {

Sim3d randomSim3(std::mt19937& rng, double rot, double trans, double log_scale) {
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  Sim3d::Tangent x;
  x << trans * U(rng), trans * U(rng), trans * U(rng), rot * U(rng), rot * U(rng), rot * U(rng),
      log_scale * U(rng);
  return Sim3d::exp(x);
}

// Numeric Jacobian of the residual with respect to a left perturbation of S_wi (which = 0) or
// S_wj (which = 1).
Matrix7d numericJacobian(const Sim3d& M, const Sim3d& S_wi, const Sim3d& S_wj, int which) {
  constexpr double h = 1e-6;
  Matrix7d J;
  for (int k = 0; k < 7; ++k) {
    Sim3d::Tangent d = Sim3d::Tangent::Zero();
    d(k) = h;
    const Sim3d pi = which == 0 ? Sim3d::exp(d) * S_wi : S_wi;
    const Sim3d pj = which == 1 ? Sim3d::exp(d) * S_wj : S_wj;
    const Sim3d mi = which == 0 ? Sim3d::exp(-d) * S_wi : S_wi;
    const Sim3d mj = which == 1 ? Sim3d::exp(-d) * S_wj : S_wj;
    J.col(k) = (sim3EdgeResidual(M, pi, pj) - sim3EdgeResidual(M, mi, mj)) / (2 * h);
  }
  return J;
}

TEST(Sim3Edge, ResidualIsZeroForAConsistentMeasurement) {
  std::mt19937 rng(1);
  const Sim3d a = randomSim3(rng, 2.0, 10.0, 1.0), b = randomSim3(rng, 2.0, 10.0, 1.0);
  EXPECT_LT(sim3EdgeResidual(a.inverse() * b, a, b).norm(), 1e-12);
  const Sim3d::Tangent d = (Sim3d::Tangent() << 0.1, 0.2, -0.1, 0.01, -0.02, 0.03, 0.05).finished();
  // Measurement off by exp(d) on the right: r = -d.
  EXPECT_LT((sim3EdgeResidual(a.inverse() * b * Sim3d::exp(d), a, b) + d).norm(), 1e-12);
}

TEST(Sim3Edge, AnalyticJacobiansMatchNumericDifferentiation) {
  std::mt19937 rng(2);
  struct Case {
    double rot, trans, log_scale, tol;  // size of the residual, tolerance (relative to |J|)
  };
  for (const Case c : {Case{1e-4, 1e-3, 1e-4, 1e-6}, Case{0.1, 1.0, 0.1, 1e-6},
                       Case{0.5, 5.0, 0.5, 1e-5}, Case{1.0, 10.0, 0.7, 1e-3}}) {
    for (int trial = 0; trial < 10; ++trial) {
      const Sim3d S_wi = randomSim3(rng, 3.0, 20.0, 1.0);
      const Sim3d S_wj = randomSim3(rng, 3.0, 20.0, 1.0);
      // The measurement disagrees with the vertices by a residual of the case's size.
      const Sim3d M = S_wi.inverse() * S_wj * randomSim3(rng, c.rot, c.trans, c.log_scale);
      Matrix7d J_i, J_j;
      const Vector7d r = sim3EdgeJacobians(M, S_wi, S_wj, &J_i, &J_j);
      EXPECT_LT((r - sim3EdgeResidual(M, S_wi, S_wj)).norm(), 1e-15);
      const Matrix7d N_i = numericJacobian(M, S_wi, S_wj, 0);
      const Matrix7d N_j = numericJacobian(M, S_wi, S_wj, 1);
      EXPECT_LT((J_i - N_i).norm(), c.tol * N_i.norm()) << "rot " << c.rot << "\n"
                                                        << J_i << "\n"
                                                        << N_i;
      EXPECT_LT((J_j - N_j).norm(), c.tol * N_j.norm()) << "rot " << c.rot;
    }
  }
}

}  // namespace
}  // namespace ldsm::loop
