#include <gtest/gtest.h>

#include <atomic>
#include <set>
#include <vector>

#include "loop/binary_kmajority.h"
#include "synthetic_descriptors.h"

namespace ldsm::loop {
namespace {

struct Clustered {
  std::vector<OrbDescriptor> centers;
  std::vector<OrbDescriptor> data;
  std::vector<int> label;
};

/// `k` random centres (pairwise ~128 bits apart), `per` members each with `noise` bits flipped,
/// interleaved so that the input order carries no information.
Clustered makeClusters(int k, int per, int noise, std::uint64_t seed) {
  SplitMix64 rng(seed);
  Clustered c;
  for (int i = 0; i < k; ++i) c.centers.push_back(test::randomDescriptor(rng));
  for (int m = 0; m < per; ++m) {
    for (int i = 0; i < k; ++i) {
      c.data.push_back(test::flipBits(c.centers[static_cast<std::size_t>(i)], noise, rng));
      c.label.push_back(i);
    }
  }
  return c;
}

std::vector<std::uint32_t> allMembers(std::size_t n) {
  std::vector<std::uint32_t> m(n);
  for (std::size_t i = 0; i < n; ++i) m[i] = static_cast<std::uint32_t>(i);
  return m;
}

TEST(KMajority, RecoversKnownClustersAndTheirExactCentres) {
  const Clustered c = makeClusters(6, 150, 24, 7);
  const auto members = allMembers(c.data.size());
  SplitMix64 rng(3);
  KMajorityResult r;
  ASSERT_TRUE(kMajority(c.data.data(), members.data(), members.size(), 6, 20, rng, r));
  ASSERT_EQ(r.centers.size(), 6u);
  // Every true cluster maps to exactly one found cluster and vice versa (purity 100 %).
  std::vector<int> found_of_label(6, -1);
  for (std::size_t i = 0; i < c.data.size(); ++i) {
    int& f = found_of_label[static_cast<std::size_t>(c.label[i])];
    if (f < 0) f = static_cast<int>(r.assignment[i]);
    EXPECT_EQ(f, static_cast<int>(r.assignment[i])) << "member " << i;
  }
  EXPECT_EQ(std::set<int>(found_of_label.begin(), found_of_label.end()).size(), 6u);
  // The bitwise majority of 150 members with 24/256 flipped bits is the true centre.
  for (int l = 0; l < 6; ++l) {
    EXPECT_EQ(hammingDistance(
                  r.centers[static_cast<std::size_t>(found_of_label[static_cast<std::size_t>(l)])],
                  c.centers[static_cast<std::size_t>(l)]),
              0);
  }
  EXPECT_GE(r.iterations, 1);
}

TEST(KMajority, IsDeterministicForASeed) {
  const Clustered c = makeClusters(5, 40, 60, 11);
  const auto members = allMembers(c.data.size());
  KMajorityResult a, b, other;
  SplitMix64 r1(9), r2(9), r3(10);
  ASSERT_TRUE(kMajority(c.data.data(), members.data(), members.size(), 8, 5, r1, a));
  ASSERT_TRUE(kMajority(c.data.data(), members.data(), members.size(), 8, 5, r2, b));
  ASSERT_TRUE(kMajority(c.data.data(), members.data(), members.size(), 8, 5, r3, other));
  EXPECT_EQ(a.centers, b.centers);
  EXPECT_EQ(a.assignment, b.assignment);
  // Another seed picks other seeds (the centres of noisy data then differ somewhere).
  EXPECT_NE(a.assignment == other.assignment && a.centers == other.centers, true);
}

TEST(KMajority, StopsAtTheNumberOfDistinctDescriptors) {
  SplitMix64 rng(5);
  const OrbDescriptor x = test::randomDescriptor(rng);
  const OrbDescriptor y = test::randomDescriptor(rng);
  std::vector<OrbDescriptor> data{x, x, y, x, y, y, x};
  const auto members = allMembers(data.size());
  KMajorityResult r;
  ASSERT_TRUE(kMajority(data.data(), members.data(), members.size(), 10, 10, rng, r));
  ASSERT_EQ(r.centers.size(), 2u);
  for (std::size_t i = 0; i < data.size(); ++i) {
    EXPECT_EQ(r.centers[r.assignment[i]], data[i]);
  }
  std::vector<OrbDescriptor> same(5, x);
  KMajorityResult one;
  ASSERT_TRUE(kMajority(same.data(), members.data(), same.size(), 4, 10, rng, one));
  ASSERT_EQ(one.centers.size(), 1u);
  EXPECT_EQ(one.centers[0], x);
}

TEST(KMajority, UsesOnlyTheGivenMembers) {
  const Clustered c = makeClusters(2, 50, 10, 21);
  // Members: only label-0 points.
  std::vector<std::uint32_t> members;
  for (std::size_t i = 0; i < c.data.size(); ++i) {
    if (c.label[i] == 0) members.push_back(static_cast<std::uint32_t>(i));
  }
  SplitMix64 rng(1);
  KMajorityResult r;
  ASSERT_TRUE(kMajority(c.data.data(), members.data(), members.size(), 1, 10, rng, r));
  ASSERT_EQ(r.centers.size(), 1u);
  EXPECT_EQ(r.assignment.size(), members.size());
  // One cluster: the seed is a member; assignment all zero.
  for (auto a : r.assignment) EXPECT_EQ(a, 0u);
}

TEST(KMajority, AbortFlagStopsClustering) {
  const Clustered c = makeClusters(4, 50, 30, 2);
  const auto members = allMembers(c.data.size());
  std::atomic<bool> abort{true};
  SplitMix64 rng(1);
  KMajorityResult r;
  EXPECT_FALSE(kMajority(c.data.data(), members.data(), members.size(), 4, 10, rng, r, &abort));
}

TEST(KMajority, NearestCenterPrefersLowerIndexOnTies) {
  SplitMix64 rng(4);
  const OrbDescriptor a = test::randomDescriptor(rng);
  const OrbDescriptor centers[3] = {test::flipBits(a, 5, rng), a, a};
  int d = -1;
  EXPECT_EQ(nearestCenter(a, centers, 3, &d), 1);
  EXPECT_EQ(d, 0);
}

}  // namespace
}  // namespace ldsm::loop
