// Hamming distances of ORB descriptors (model/orb_descriptor.h) and the popcount dispatch
// (model/popcount_dispatch.h): a function compiled as POPCNT and baseline clones must count the
// same bits as a plain bit-by-bit reference, and so must the matcher built on it.
#include "model/popcount_dispatch.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "features/orb_matching.h"
#include "model/orb_descriptor.h"

namespace ldsm {
namespace {

/// Bit i of the descriptor (bit i % 64 of word i / 64).
bool bit(const OrbDescriptor& d, int i) {
  return ((d[i / 64] >> (i % 64)) & 1u) != 0;
}

/// Hamming distance one bit at a time (no popcount).
int referenceDistance(const OrbDescriptor& a, const OrbDescriptor& b) {
  int n = 0;
  for (int i = 0; i < 256; ++i) n += bit(a, i) != bit(b, i) ? 1 : 0;
  return n;
}

/// The same distance through the dispatched clones (the resolver picks one at load time: the
/// POPCNT clone on a CPU that has it, so only that one is exercised there).
LDSM_POPCNT_CLONES
int dispatchedDistance(const OrbDescriptor& a, const OrbDescriptor& b) {
  return hammingDistance(a, b);
}

LDSM_POPCNT_CLONES
int dispatchedSum(const std::vector<OrbDescriptor>& set, const OrbDescriptor& q) {
  int sum = 0;
  for (const OrbDescriptor& d : set) sum += hammingDistance(d, q);
  return sum;
}

OrbDescriptor randomDescriptor(std::mt19937_64& rng) {
  return {rng(), rng(), rng(), rng()};
}

/// A descriptor with about `density` of its bits set.
OrbDescriptor sparse(std::mt19937_64& rng, double density) {
  std::bernoulli_distribution on(density);
  OrbDescriptor d{};
  for (int i = 0; i < 256; ++i)
    if (on(rng)) d[i / 64] |= std::uint64_t{1} << (i % 64);
  return d;
}

TEST(PopcountDispatch, DispatchedDistanceAgreesWithTheBitwiseReference) {
  std::mt19937_64 rng(2024);
  for (int i = 0; i < 20000; ++i) {
    const double density = (i % 5) / 4.0;  // 0, 1/4, 1/2, 3/4, all bits
    const OrbDescriptor a = i % 2 ? randomDescriptor(rng) : sparse(rng, density);
    const OrbDescriptor b = sparse(rng, 1.0 - density);
    const int ref = referenceDistance(a, b);
    ASSERT_EQ(dispatchedDistance(a, b), ref) << "pair " << i;
    ASSERT_EQ(hammingDistance(a, b), ref) << "pair " << i;
  }
  std::vector<OrbDescriptor> set;
  for (int i = 0; i < 500; ++i) set.push_back(randomDescriptor(rng));
  const OrbDescriptor q = randomDescriptor(rng);
  int ref = 0;
  for (const OrbDescriptor& d : set) ref += referenceDistance(d, q);
  EXPECT_EQ(dispatchedSum(set, q), ref);
}

TEST(PopcountDispatch, HammingDistanceExtremesAndSingleBits) {
  const OrbDescriptor zero{}, ones{~0ull, ~0ull, ~0ull, ~0ull};
  EXPECT_EQ(dispatchedDistance(zero, zero), 0);
  EXPECT_EQ(dispatchedDistance(zero, ones), 256);
  EXPECT_EQ(dispatchedDistance(ones, zero), 256);
  // Every single bit, in every word, including each word's top bit, counts exactly once.
  for (int i = 0; i < 256; ++i) {
    OrbDescriptor d{};
    d[i / 64] = std::uint64_t{1} << (i % 64);
    ASSERT_EQ(dispatchedDistance(zero, d), 1) << "bit " << i;
    ASSERT_EQ(dispatchedDistance(ones, d), 255) << "bit " << i;
  }
}

TEST(PopcountDispatch, HammingDistanceIsAMetric) {
  std::mt19937_64 rng(7);
  for (int i = 0; i < 2000; ++i) {
    const OrbDescriptor a = randomDescriptor(rng), b = randomDescriptor(rng),
                        c = randomDescriptor(rng);
    EXPECT_EQ(dispatchedDistance(a, a), 0);
    EXPECT_EQ(dispatchedDistance(a, b), dispatchedDistance(b, a));
    EXPECT_LE(dispatchedDistance(a, c), dispatchedDistance(a, b) + dispatchedDistance(b, c));
    const OrbDescriptor not_a{~a[0], ~a[1], ~a[2], ~a[3]};
    EXPECT_EQ(dispatchedDistance(a, not_a), 256);
  }
}

TEST(PopcountDispatch, MatcherFindsTheBitwiseNearestDescriptor) {
  // matchOrb's search is a dispatched clone: its matches must be the reference's nearest.
  std::mt19937_64 rng(99);
  std::vector<OrbDescriptor> train, query;
  for (int i = 0; i < 300; ++i) train.push_back(randomDescriptor(rng));
  std::uniform_int_distribution<int> bitpos(0, 255);
  for (int i = 0; i < 300; i += 2) {  // noisy copies of every other train descriptor
    OrbDescriptor d = train[i];
    for (int k = 0; k < 10; ++k) {
      const int b = bitpos(rng);
      d[b / 64] ^= std::uint64_t{1} << (b % 64);
    }
    query.push_back(d);
  }
  for (int i = 0; i < 50; ++i) query.push_back(randomDescriptor(rng));  // matching nothing
  const std::vector<std::pair<int, int>> matches = matchOrb(query, train);
  int copies_matched = 0;
  for (const auto& [q, t] : matches) {
    int best = -1, best_dist = 257;
    for (int j = 0; j < static_cast<int>(train.size()); ++j) {
      const int d = referenceDistance(query[q], train[j]);
      if (d < best_dist) {
        best_dist = d;
        best = j;
      }
    }
    EXPECT_EQ(t, best) << "query " << q;
    EXPECT_LE(best_dist, 64);
    if (q < 150 && t == 2 * q) ++copies_matched;
  }
  EXPECT_EQ(copies_matched, 150);
  EXPECT_EQ(static_cast<int>(matches.size()), 150);
}

}  // namespace
}  // namespace ldsm
