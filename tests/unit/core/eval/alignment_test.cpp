#include "ldsm/eval/alignment.h"

#include <gtest/gtest.h>

#include <random>

#include "ldsm/error.h"

namespace ldsm::eval {
namespace {

std::vector<Eigen::Vector3d> randomPoints(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  std::vector<Eigen::Vector3d> pts;
  for (std::size_t i = 0; i < n; ++i) pts.emplace_back(u(rng), u(rng), u(rng));
  return pts;
}

Alignment knownSim3() {
  Alignment a;
  a.rotation = Eigen::AngleAxisd(2.1, Eigen::Vector3d(0.3, -0.5, 0.8).normalized()).matrix();
  a.translation = Eigen::Vector3d(4.0, -2.0, 0.5);
  a.scale = 0.37;
  return a;
}

TEST(Alignment, RecoversKnownSim3) {
  const Alignment truth = knownSim3();
  const auto est = randomPoints(50, 1);
  std::vector<Eigen::Vector3d> gt;
  for (const auto& p : est) gt.push_back(truth.apply(p));
  const Alignment a = alignUmeyama(est, gt, true);
  EXPECT_NEAR(a.scale, truth.scale, 1e-12);
  EXPECT_LT((a.rotation - truth.rotation).norm(), 1e-12);
  EXPECT_LT((a.translation - truth.translation).norm(), 1e-11);
  EXPECT_NEAR(a.rotation.determinant(), 1.0, 1e-12);
}

TEST(Alignment, RigidModeKeepsScaleOne) {
  Alignment truth = knownSim3();
  truth.scale = 1.0;
  const auto est = randomPoints(10, 2);
  std::vector<Eigen::Vector3d> gt;
  for (const auto& p : est) gt.push_back(truth.apply(p));
  const Alignment a = alignUmeyama(est, gt, false);
  EXPECT_EQ(a.scale, 1.0);
  EXPECT_LT((a.rotation - truth.rotation).norm(), 1e-12);
  EXPECT_LT((a.translation - truth.translation).norm(), 1e-11);
}

TEST(Alignment, ProperRotationForReflectedPoints) {
  // gt is a mirror image of est: the best *proper* rotation must still have det +1.
  const auto est = randomPoints(20, 3);
  std::vector<Eigen::Vector3d> gt;
  for (const auto& p : est) gt.emplace_back(p.x(), p.y(), -p.z());
  const Alignment a = alignUmeyama(est, gt, true);
  EXPECT_NEAR(a.rotation.determinant(), 1.0, 1e-12);
}

TEST(Alignment, PlanarPointsAreFine) {
  std::vector<Eigen::Vector3d> est{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  const Alignment truth = knownSim3();
  std::vector<Eigen::Vector3d> gt;
  for (const auto& p : est) gt.push_back(truth.apply(p));
  const Alignment a = alignUmeyama(est, gt, true);
  EXPECT_LT((a.rotation - truth.rotation).norm(), 1e-12);
  EXPECT_NEAR(a.scale, truth.scale, 1e-12);
}

TEST(Alignment, ComposeAndInverse) {
  const Alignment a = knownSim3();
  Alignment b;
  b.rotation = Eigen::AngleAxisd(-0.7, Eigen::Vector3d::UnitY()).matrix();
  b.translation = Eigen::Vector3d(0.1, 0.2, 0.3);
  b.scale = 2.5;
  const Eigen::Vector3d p(1.0, -2.0, 3.0);
  EXPECT_LT(((a * b).apply(p) - a.apply(b.apply(p))).norm(), 1e-12);
  EXPECT_LT((a.inverse().apply(a.apply(p)) - p).norm(), 1e-12);
  EXPECT_NEAR(a.rotationAngle(), 2.1, 1e-12);
}

TEST(Alignment, DegenerateInputIsRejected) {
  const std::vector<Eigen::Vector3d> two{{0, 0, 0}, {1, 0, 0}};
  EXPECT_THROW(alignUmeyama(two, two, true), InputError);

  const auto three = randomPoints(3, 4);
  const auto four = randomPoints(4, 5);
  EXPECT_THROW(alignUmeyama(three, four, true), InputError);

  std::vector<Eigen::Vector3d> line;
  for (int i = 0; i < 10; ++i) line.emplace_back(0.5 * i, 1.0 * i, -0.2 * i);
  const auto scattered = randomPoints(10, 6);
  try {
    alignUmeyama(line, scattered, true);
    FAIL() << "collinear input accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("collinear"), std::string::npos) << e.what();
  }
  EXPECT_THROW(alignUmeyama(scattered, line, false), InputError);

  const std::vector<Eigen::Vector3d> same(5, Eigen::Vector3d(1, 2, 3));
  try {
    alignUmeyama(same, randomPoints(5, 7), true);
    FAIL() << "coincident input accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("coincide"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ldsm::eval
