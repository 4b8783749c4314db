// k-majority clustering of binary descriptors (k-medians under the Hamming distance, Grana et
// al. 2013): greedy k-means++ seeding (Arthur & Vassilvitskii 2007: candidates drawn with
// probability proportional to the squared distance to the nearest chosen centre; of 2 + ln k
// candidates the one that lowers the total squared distance most is kept), then alternating
// nearest-centre assignment and bitwise-majority centres until the assignment no longer changes.
// Deterministic: the only randomness comes from the caller's seeded SplitMix64.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "loop/loop_types.h"

namespace ldsm::loop {

/// SplitMix64 (Steele, Lea & Flood 2014): a tiny, portable, seedable 64-bit generator, so that
/// training gives the same vocabulary on every platform and standard library.
class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  /// Uniform integer in [0, n) (n > 0; modulo bias below 2^-40 for n < 2^24).
  std::uint64_t below(std::uint64_t n) { return next() % n; }

 private:
  std::uint64_t state_;
};

/// Result of kMajority(): the non-empty clusters' centres and, for each member, its centre.
struct KMajorityResult {
  std::vector<OrbDescriptor> centers;
  std::vector<std::uint32_t> assignment;  ///< index into centers, per member
  int iterations = 0;                     ///< assignment/update rounds run
};

/// Clusters the descriptors `all[members[i]]`, i < n, into at most k clusters. Fewer clusters
/// come out when there are fewer than k distinct descriptors (seeding stops when every member
/// coincides with a centre) or a cluster empties (it is dropped). Ties go to the lower centre
/// index; a majority tie (exactly half the members set) gives a 0 bit. Runs at most
/// max_iterations update rounds. Returns false, leaving `out` unspecified, when `abort` becomes
/// true. Requires n > 0, k >= 1.
bool kMajority(const OrbDescriptor* all, const std::uint32_t* members, std::size_t n, int k,
               int max_iterations, SplitMix64& rng, KMajorityResult& out,
               const std::atomic<bool>* abort = nullptr);

/// Index of the centre nearest to `d` (lowest index on ties) and its distance.
int nearestCenter(const OrbDescriptor& d, const OrbDescriptor* centers, int count, int* distance);

}  // namespace ldsm::loop
