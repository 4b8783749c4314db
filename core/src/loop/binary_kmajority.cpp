#include "loop/binary_kmajority.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "model/popcount_dispatch.h"

namespace ldsm::loop {
namespace {

/// Per-bit counts of a set of descriptors. Additions go to eight bit-sliced planes (a ripple-carry
/// counter per bit, 0..255), which are flushed into 32-bit totals every 255 additions: a few word
/// operations per descriptor instead of 256 bit extractions.
class BitCounter {
 public:
  void add(const OrbDescriptor& d) {
    for (std::size_t w = 0; w < 4; ++w) {
      std::uint64_t carry = d[w];
      for (std::size_t p = 0; p < kPlanes && carry != 0; ++p) {
        const std::uint64_t next = planes_[p][w] & carry;
        planes_[p][w] ^= carry;
        carry = next;
      }
    }
    ++count_;
    if (++pending_ == kFlushEvery) flush();
  }

  /// Bitwise majority: bit set when more than half of the added descriptors have it.
  OrbDescriptor majority() {
    flush();
    OrbDescriptor m{};
    for (std::size_t bit = 0; bit < 256; ++bit) {
      if (2 * static_cast<std::uint64_t>(totals_[bit]) > count_) m[bit / 64] |= 1ull << (bit % 64);
    }
    return m;
  }
  std::uint64_t count() const { return count_; }

 private:
  static constexpr std::size_t kPlanes = 8;
  static constexpr int kFlushEvery = 255;

  void flush() {
    if (pending_ == 0) return;
    for (std::size_t bit = 0; bit < 256; ++bit) {
      const std::size_t w = bit / 64;
      const unsigned b = static_cast<unsigned>(bit % 64);
      std::uint32_t v = 0;
      for (std::size_t p = 0; p < kPlanes; ++p) {
        v |= static_cast<std::uint32_t>((planes_[p][w] >> b) & 1u) << p;
      }
      totals_[bit] += v;
    }
    for (auto& plane : planes_) plane = {};
    pending_ = 0;
  }

  std::array<std::array<std::uint64_t, 4>, kPlanes> planes_{};
  std::array<std::uint32_t, 256> totals_{};
  std::uint64_t count_ = 0;
  int pending_ = 0;
};

LDSM_POPCNT_CLONES
bool assignAll(const OrbDescriptor* all, const std::uint32_t* members, std::size_t n,
               const OrbDescriptor* centers, int k, std::uint32_t* assignment) {
  bool changed = false;
  for (std::size_t i = 0; i < n; ++i) {
    const OrbDescriptor& d = all[members[i]];
    int best = 0;
    int best_distance = std::numeric_limits<int>::max();
    for (int c = 0; c < k; ++c) {
      const int dist = hammingDistance(d, centers[c]);
      if (dist < best_distance) {
        best_distance = dist;
        best = c;
      }
    }
    if (assignment[i] != static_cast<std::uint32_t>(best)) {
      assignment[i] = static_cast<std::uint32_t>(best);
      changed = true;
    }
  }
  return changed;
}

/// min_sq[i] = min(min_sq[i], d(x_i, c)^2); returns the new sum.
LDSM_POPCNT_CLONES
std::uint64_t lowerSquaredDistances(const OrbDescriptor* all, const std::uint32_t* members,
                                    std::size_t n, const OrbDescriptor& c, std::uint32_t* min_sq) {
  std::uint64_t sum = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t d = static_cast<std::uint32_t>(hammingDistance(all[members[i]], c));
    const std::uint32_t sq = d * d;
    if (sq < min_sq[i]) min_sq[i] = sq;
    sum += min_sq[i];
  }
  return sum;
}

/// Sum over members of min(min_sq[i], d(x_i, c)^2): the potential if c became a centre.
LDSM_POPCNT_CLONES
std::uint64_t potentialWith(const OrbDescriptor* all, const std::uint32_t* members, std::size_t n,
                            const OrbDescriptor& c, const std::uint32_t* min_sq) {
  std::uint64_t sum = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t d = static_cast<std::uint32_t>(hammingDistance(all[members[i]], c));
    sum += std::min(d * d, min_sq[i]);
  }
  return sum;
}

}  // namespace

LDSM_POPCNT_CLONES
int nearestCenter(const OrbDescriptor& d, const OrbDescriptor* centers, int count, int* distance) {
  int best = 0;
  int best_distance = std::numeric_limits<int>::max();
  for (int c = 0; c < count; ++c) {
    const int dist = hammingDistance(d, centers[c]);
    if (dist < best_distance) {
      best_distance = dist;
      best = c;
    }
  }
  if (distance != nullptr) *distance = best_distance;
  return best;
}

bool kMajority(const OrbDescriptor* all, const std::uint32_t* members, std::size_t n, int k,
               int max_iterations, SplitMix64& rng, KMajorityResult& out,
               const std::atomic<bool>* abort) {
  out.centers.clear();
  out.iterations = 0;
  out.assignment.assign(n, 0u);
  if (n == 0 || k < 1) return true;

  // Greedy k-means++ seeding: each new centre is the best (lowest potential) of a few candidates
  // drawn with probability proportional to the squared distance to the nearest centre so far.
  const int trials = 2 + static_cast<int>(std::log(static_cast<double>(k)));
  std::vector<std::uint32_t> min_sq(n, std::numeric_limits<std::uint32_t>::max());
  std::vector<std::uint64_t> cumulative(n);
  out.centers.push_back(all[members[rng.below(n)]]);
  std::uint64_t sum = lowerSquaredDistances(all, members, n, out.centers.back(), min_sq.data());
  while (static_cast<int>(out.centers.size()) < k && sum > 0) {
    std::uint64_t acc = 0;
    for (std::size_t i = 0; i < n; ++i) cumulative[i] = (acc += min_sq[i]);
    std::size_t best = n;
    std::uint64_t best_potential = std::numeric_limits<std::uint64_t>::max();
    for (int t = 0; t < trials; ++t) {
      const std::uint64_t target = rng.below(sum);
      const std::size_t pick = static_cast<std::size_t>(
          std::upper_bound(cumulative.begin(), cumulative.end(), target) - cumulative.begin());
      const std::uint64_t potential =
          potentialWith(all, members, n, all[members[pick]], min_sq.data());
      if (potential < best_potential) {
        best_potential = potential;
        best = pick;
      }
    }
    out.centers.push_back(all[members[best]]);
    sum = lowerSquaredDistances(all, members, n, out.centers.back(), min_sq.data());
  }
  // Every seed is a member at distance 0 from its own (distinct) centre: no cluster is empty.
  assignAll(all, members, n, out.centers.data(), static_cast<int>(out.centers.size()),
            out.assignment.data());
  if (out.centers.size() == 1) return true;

  std::vector<BitCounter> counters;
  std::vector<std::uint32_t> remap;
  for (int it = 0; it < max_iterations; ++it) {
    if (abort != nullptr && abort->load(std::memory_order_relaxed)) return false;
    counters.assign(out.centers.size(), BitCounter());
    for (std::size_t i = 0; i < n; ++i) counters[out.assignment[i]].add(all[members[i]]);
    // New centres; empty clusters are dropped.
    bool dropped = false;
    std::size_t kept = 0;
    remap.assign(out.centers.size(), 0u);
    for (std::size_t c = 0; c < out.centers.size(); ++c) {
      if (counters[c].count() == 0) {
        dropped = true;
        continue;
      }
      remap[c] = static_cast<std::uint32_t>(kept);
      out.centers[kept++] = counters[c].majority();
    }
    out.centers.resize(kept);
    if (dropped) {
      for (std::uint32_t& a : out.assignment) a = remap[a];
    }
    ++out.iterations;
    const bool changed = assignAll(all, members, n, out.centers.data(),
                                   static_cast<int>(out.centers.size()), out.assignment.data());
    if (!changed && !dropped) break;
  }
  // A majority update can leave a centre without members (another, closer centre took them all);
  // drop such centres so that every cluster is non-empty.
  std::vector<std::uint32_t> sizes(out.centers.size(), 0u);
  for (std::uint32_t a : out.assignment) ++sizes[a];
  std::size_t kept = 0;
  remap.assign(out.centers.size(), 0u);
  for (std::size_t c = 0; c < out.centers.size(); ++c) {
    if (sizes[c] == 0) continue;
    remap[c] = static_cast<std::uint32_t>(kept);
    out.centers[kept++] = out.centers[c];
  }
  if (kept != out.centers.size()) {
    out.centers.resize(kept);
    for (std::uint32_t& a : out.assignment) a = remap[a];
  }
  return true;
}

}  // namespace ldsm::loop
