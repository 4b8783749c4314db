// The binary descriptor of a corner, shared by tracking-side feature extraction and loop closure.
#pragma once

#include <array>
#include <cstdint>

namespace ldsm {

/// A 256-bit ORB (rBRIEF) descriptor, bit i of the descriptor in bit (i % 64) of word i / 64.
using OrbDescriptor = std::array<std::uint64_t, 4>;

/// Hamming distance of two descriptors (0..256).
inline int hammingDistance(const OrbDescriptor& a, const OrbDescriptor& b) {
  int d = 0;
  for (int i = 0; i < 4; ++i) d += __builtin_popcountll(a[i] ^ b[i]);
  return d;
}

}  // namespace ldsm
