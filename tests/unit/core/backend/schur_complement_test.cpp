// subtractDepthSchur (the window solve's and the calibration envelope's depth elimination)
// against its dense definition, and with a scratch matrix kept from a larger call.
#include "backend/schur_complement.h"

#include <gtest/gtest.h>

#include <random>

namespace ldsm {
namespace {

struct Case {
  Eigen::MatrixXd A, C;
  Eigen::VectorXd inv_d;
};

Case randomCase(int dim, int points, std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  std::uniform_real_distribution<double> u(0.0, 2.0);
  Case c;
  const Eigen::MatrixXd R = Eigen::MatrixXd::NullaryExpr(dim, dim, [&] { return n(rng); });
  c.A = R * R.transpose() + dim * Eigen::MatrixXd::Identity(dim, dim);
  c.C = Eigen::MatrixXd::NullaryExpr(dim, points, [&] { return n(rng); });
  c.inv_d = Eigen::VectorXd::NullaryExpr(points, [&] { return u(rng); });
  c.inv_d[0] = 0.0;  // a fixed point: no Schur term
  return c;
}

TEST(SchurComplement, EqualsTheDenseProductAndStaysSymmetric) {
  std::mt19937 rng(11);
  for (const auto& [dim, points] : {std::pair{8, 3}, {24, 100}, {56, 700}}) {
    Case c = randomCase(dim, points, rng);
    const Eigen::MatrixXd expected = c.A - c.C * c.inv_d.asDiagonal() * c.C.transpose();
    Eigen::MatrixXd A = c.A;
    subtractDepthSchur(A, c.C, c.inv_d);
    EXPECT_LT((A - expected).norm(), 1e-10 * expected.norm()) << dim << " x " << points;
    EXPECT_EQ(A, A.transpose());
  }
}

// The mapper keeps one scratch from keyframe to keyframe: grown once, then only its first columns
// are used. The result must be the one a fresh scratch of the exact size gives, bit for bit,
// also when the coupling is a view of the first columns of a larger matrix (the window's kept
// coupling buffer).
TEST(SchurComplement, AKeptScratchAndAColumnViewGiveTheSameBits) {
  std::mt19937 rng(12);
  Eigen::MatrixXd kept;
  for (const int points : {900, 300, 1100, 40}) {
    Case c = randomCase(56, points, rng);
    Eigen::MatrixXd fresh_scratch;
    Eigen::MatrixXd fresh = c.A;
    subtractDepthSchur(fresh, c.C, c.inv_d, fresh_scratch);
    EXPECT_EQ(fresh_scratch.rows(), 56);
    EXPECT_GE(fresh_scratch.cols(), points);

    Eigen::MatrixXd buffer(56, points + 123);
    buffer.setConstant(7.0);
    buffer.leftCols(points) = c.C;
    Eigen::MatrixXd reused = c.A;
    subtractDepthSchur(reused, buffer.leftCols(points), c.inv_d, kept);
    EXPECT_EQ(reused, fresh) << points << " points";
    EXPECT_GE(kept.cols(), points);
  }
  EXPECT_GE(kept.cols(), 1100);  // grown once, never shrunk
}

}  // namespace
}  // namespace ldsm
