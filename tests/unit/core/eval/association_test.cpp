#include "ldsm/eval/association.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "ldsm/error.h"

namespace ldsm::eval {
namespace {

Trajectory stamps(const std::vector<double>& times) {
  Trajectory t;
  for (double s : times) {
    StampedPose sp;
    sp.timestamp = s;
    t.push_back(sp);
  }
  return t;
}

TEST(Association, OffsetJitterAndMissingPoses) {
  // Ground truth at 10 Hz with every 5th pose missing; estimate at the same rate, offset by
  // 4 ms, jittered by up to 3 ms, with every 7th pose missing, plus poses far outside.
  std::vector<double> gt_t;
  for (int i = 0; i < 300; ++i) {
    if (i % 5 != 3) gt_t.push_back(0.1 * i);
  }
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> jitter(-0.003, 0.003);
  std::vector<double> est_t{-5.0};
  std::vector<int> est_frame{-1};
  for (int i = 0; i < 300; ++i) {
    if (i % 7 == 2) continue;
    est_t.push_back(0.1 * i + 0.004 + jitter(rng));
    est_frame.push_back(i);
  }
  est_t.push_back(100.0);
  est_frame.push_back(-1);

  const Trajectory gt = stamps(gt_t);
  const Trajectory est = stamps(est_t);
  const auto pairs = associate(gt, est, 0.01);

  std::size_t expected = 0;
  for (int f : est_frame) {
    if (f >= 0 && f % 5 != 3) ++expected;
  }
  ASSERT_EQ(pairs.size(), expected);
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const auto& p = pairs[k];
    if (k > 0) {
      EXPECT_GT(p.est, pairs[k - 1].est);
    }
    const int frame = est_frame[p.est];
    ASSERT_GE(frame, 0);
    EXPECT_NEAR(gt[p.gt].timestamp, 0.1 * frame, 1e-9);
    EXPECT_LE(std::abs(gt[p.gt].timestamp - est[p.est].timestamp), 0.01);
  }
}

TEST(Association, OneToOneNearestWins) {
  const Trajectory gt = stamps({1.0, 2.0});
  const Trajectory est = stamps({0.995, 1.001, 1.009, 2.05});
  const auto pairs = associate(gt, est, 0.02);
  ASSERT_EQ(pairs.size(), 1u);  // 2.05 is out of tolerance; only the closest to 1.0 is used
  EXPECT_EQ(pairs[0].gt, 0u);
  EXPECT_EQ(pairs[0].est, 1u);
}

TEST(Association, UnsortedGroundTruth) {
  const Trajectory gt = stamps({3.0, 1.0, 2.0});
  const Trajectory est = stamps({1.0, 2.0, 3.0});
  const auto pairs = associate(gt, est, 0.001);
  ASSERT_EQ(pairs.size(), 3u);
  EXPECT_EQ(pairs[0].gt, 1u);
  EXPECT_EQ(pairs[1].gt, 2u);
  EXPECT_EQ(pairs[2].gt, 0u);
}

TEST(Association, ZeroToleranceMatchesExactStamps) {
  const Trajectory gt = stamps({0.0, 0.5, 1.0});
  const Trajectory est = stamps({0.5, 0.75, 1.0});
  EXPECT_EQ(associate(gt, est, 0.0).size(), 2u);
}

TEST(Association, BadToleranceIsAConfigError) {
  const Trajectory t = stamps({0.0});
  EXPECT_THROW(associate(t, t, -0.1), ConfigError);
  EXPECT_THROW(associate(t, t, std::nan("")), ConfigError);
}

TEST(Association, PathLength) {
  EXPECT_DOUBLE_EQ(pathLength({{0, 0, 0}, {3, 4, 0}, {3, 4, 2}}), 7.0);
  EXPECT_DOUBLE_EQ(pathLength({}), 0.0);
}

}  // namespace
}  // namespace ldsm::eval
