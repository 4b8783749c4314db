#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <vector>

#include "ldsm/error.h"
#include "loop/binary_kmajority.h"
#include "loop/epipolar_check.h"

namespace ldsm::loop {
namespace {

/// Random points in front of two cameras 0.5 m apart with a small rotation, projected with a
/// 500 px focal length; the first `outliers` matches are shuffled to wrong partners.
struct TwoViews {
  std::vector<Eigen::Vector2f> a, b;
  std::vector<DescriptorMatch> matches;
};

TwoViews makeViews(int n, int outliers, std::uint64_t seed) {
  SplitMix64 rng(seed);
  auto uniform = [&rng](double lo, double hi) {
    return lo + (hi - lo) * static_cast<double>(rng.below(1000000)) / 1e6;
  };
  const Eigen::Matrix3d r =
      Eigen::AngleAxisd(0.1, Eigen::Vector3d(0.2, 1, 0.1).normalized()).toRotationMatrix();
  const Eigen::Vector3d t(0.5, 0.05, 0.1);
  TwoViews v;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d p(uniform(-2, 2), uniform(-1.5, 1.5), uniform(3, 8));
    const Eigen::Vector3d q = r * p + t;
    v.a.emplace_back(static_cast<float>(320 + 500 * p.x() / p.z()),
                     static_cast<float>(240 + 500 * p.y() / p.z()));
    v.b.emplace_back(static_cast<float>(320 + 500 * q.x() / q.z()),
                     static_cast<float>(240 + 500 * q.y() / q.z()));
    v.matches.push_back({static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(i), 10});
  }
  for (int i = 0; i < outliers; ++i) {
    v.matches[static_cast<std::size_t>(i)].train = static_cast<std::uint32_t>((i * 37 + 11) % n);
  }
  return v;
}

TEST(EpipolarCheck, AcceptsAConsistentViewPairAndCountsItsInliers) {
  const TwoViews v = makeViews(120, 30, 1);
  const EpipolarCheckResult r = checkEpipolar(v.a, v.b, v.matches);
  EXPECT_TRUE(r.accepted);
  EXPECT_EQ(r.matches, 120);
  EXPECT_GE(r.inliers, 88);  // the 90 true matches (a shuffled one may fall on its line)
  EXPECT_LE(r.inliers, 100);
}

TEST(EpipolarCheck, RejectsRandomMatchesAndTooFewMatches) {
  TwoViews v = makeViews(120, 120, 2);
  EXPECT_FALSE(checkEpipolar(v.a, v.b, v.matches).accepted);
  v = makeViews(EpipolarCheckSettings().min_inliers - 1, 0, 3);
  const EpipolarCheckResult few = checkEpipolar(v.a, v.b, v.matches);  // < min_inliers
  EXPECT_FALSE(few.accepted);
  EXPECT_EQ(few.inliers, 0);
  v.matches.push_back({500, 0, 1});
  EpipolarCheckSettings s;
  s.min_inliers = 10;
  EXPECT_THROW(checkEpipolar(v.a, v.b, v.matches, s), InputError);
}

}  // namespace
}  // namespace ldsm::loop
