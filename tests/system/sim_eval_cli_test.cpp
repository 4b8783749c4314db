// `ldsm sim` then `ldsm eval`: the scene's ground truth against a copy moved by a Sim(3) gives
// ATE ~ 0; against a copy with known noise it gives that noise.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "ldsm/drivers/trajectory_io.h"
#include "math/sim3.h"
#include "test_paths.h"

namespace ldsm {
namespace {

double ateFromSummary(const std::string& out) {
  const auto pos = out.find("ATE rmse ");
  if (pos == std::string::npos) return -1.0;
  return std::stod(out.substr(pos + 9));
}

TEST(SimEvalCli, Sim3MovedCopyHasZeroErrorAndNoiseGivesItsRmse) {
  const std::string dir = test::scratchDir("sim_eval_cli");
  std::string out;
  ASSERT_EQ(
      test::runCommand(std::string(LDSM_EXE) + " sim --scene short --out " + dir + "/scene", &out),
      0)
      << out;
  const Trajectory gt = drivers::readTrajectory(dir + "/scene/groundtruth.txt");
  ASSERT_GT(gt.size(), 30u);

  // A copy under a known similarity transform.
  const Sim3d S(SO3d::exp(Eigen::Vector3d(0.3, -0.2, 1.1)), Eigen::Vector3d(4.0, -2.0, 7.5), 2.7);
  Trajectory moved = gt;
  for (auto& p : moved) {
    p.pose.translation = S * p.pose.translation;
    p.pose.rotation = S.so3().quaternion() * p.pose.rotation;
  }
  drivers::writeTumTrajectory(dir + "/moved.txt", moved);
  ASSERT_EQ(test::runCommand(std::string(LDSM_EXE) + " eval --gt " + dir +
                                 "/scene/groundtruth.txt --est " + dir + "/moved.txt --json " +
                                 dir + "/moved.json",
                             &out),
            0)
      << out;
  EXPECT_LT(ateFromSummary(out), 1e-6) << out;
  EXPECT_GE(ateFromSummary(out), 0.0) << out;

  // A copy with Gaussian noise of sigma per axis: ATE ~ sigma * sqrt(3).
  const double sigma = 0.01;
  std::mt19937 rng(42);
  std::normal_distribution<double> N(0.0, sigma);
  Trajectory noisy = gt;
  for (auto& p : noisy) p.pose.translation += Eigen::Vector3d(N(rng), N(rng), N(rng));
  drivers::writeTumTrajectory(dir + "/noisy.txt", noisy);
  ASSERT_EQ(test::runCommand(std::string(LDSM_EXE) + " eval --gt " + dir +
                                 "/scene/groundtruth.txt --est " + dir + "/noisy.txt",
                             &out),
            0)
      << out;
  const double expected = sigma * std::sqrt(3.0);
  EXPECT_NEAR(ateFromSummary(out), expected, 0.25 * expected) << out;
}

}  // namespace
}  // namespace ldsm
