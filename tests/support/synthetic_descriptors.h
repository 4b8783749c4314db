// Synthetic binary descriptors with known structure for the bag-of-words tests.
#pragma once

#include <cstdint>
#include <vector>

#include "loop/binary_kmajority.h"
#include "loop/loop_types.h"

namespace ldsm::loop::test {

inline OrbDescriptor randomDescriptor(SplitMix64& rng) {
  return {rng.next(), rng.next(), rng.next(), rng.next()};
}

/// `d` with `bits` distinct random bits flipped.
inline OrbDescriptor flipBits(OrbDescriptor d, int bits, SplitMix64& rng) {
  OrbDescriptor mask{};
  int flipped = 0;
  while (flipped < bits) {
    const auto b = static_cast<unsigned>(rng.below(256));
    std::uint64_t& w = mask[b / 64];
    const std::uint64_t m = 1ull << (b % 64);
    if (w & m) continue;
    w |= m;
    ++flipped;
  }
  for (int i = 0; i < 4; ++i) d[i] ^= mask[i];
  return d;
}

/// `count` random descriptors (for data without structure).
inline std::vector<OrbDescriptor> randomDescriptors(int count, SplitMix64& rng) {
  std::vector<OrbDescriptor> p;
  for (int i = 0; i < count; ++i) p.push_back(randomDescriptor(rng));
  return p;
}

/// A visual world like real images have: descriptors cluster around "appearance" centres (image
/// patches that look alike), so that features are noisy copies of a few thousand centres.
struct VisualWorld {
  std::vector<OrbDescriptor> centres;
  explicit VisualWorld(int count, SplitMix64& rng) : centres(randomDescriptors(count, rng)) {}

  /// A place: `features` centres drawn at random (the patches seen there).
  std::vector<OrbDescriptor> place(int features, SplitMix64& rng) const {
    std::vector<OrbDescriptor> p;
    for (int i = 0; i < features; ++i) p.push_back(centres[rng.below(centres.size())]);
    return p;
  }

  /// One view of a place: each feature seen with probability `keep` with `noise_bits` bits
  /// flipped, plus `clutter` features of random centres (things not part of the place).
  std::vector<OrbDescriptor> view(const std::vector<OrbDescriptor>& place, double keep,
                                  int noise_bits, int clutter, SplitMix64& rng) const {
    std::vector<OrbDescriptor> v;
    for (const OrbDescriptor& d : place) {
      if (static_cast<double>(rng.below(1000)) < keep * 1000.0) {
        v.push_back(flipBits(d, noise_bits, rng));
      }
    }
    for (int i = 0; i < clutter; ++i) {
      v.push_back(flipBits(centres[rng.below(centres.size())], noise_bits, rng));
    }
    return v;
  }
};

}  // namespace ldsm::loop::test
