// Shared pieces of the lock-free pipeline primitives (pipeline/*.h): the cache-line size used to
// keep the producer's and the consumer's indices apart, and the capacity check of the rings.
#pragma once

#include <cstddef>
#include <string>

#include "ldsm/error.h"

namespace ldsm::concurrency {

/// Alignment that keeps two atomics on different cache lines (64 bytes on x86-64 and on the
/// Cortex-A cores ldsm targets). A constant rather than hardware_destructive_interference_size,
/// whose value may differ between translation units compiled with different flags.
inline constexpr std::size_t kCacheLine = 64;

/// Smallest power of two >= n (1 for n = 0).
constexpr std::size_t nextPowerOfTwo(std::size_t n) {
  std::size_t p = 1;
  while (p < n) p <<= 1;
  return p;
}

constexpr bool isPowerOfTwo(std::size_t n) {
  return n != 0 && (n & (n - 1)) == 0;
}

/// Throws ldsm::ConfigError unless `capacity` is a power of two between `min_capacity` and 2^30.
/// (The sequence-numbered rings need two slots: with one, "element i stored" and "free for
/// element i + 1" would be the same sequence number.)
inline void checkRingCapacity(std::size_t capacity, const char* what,
                              std::size_t min_capacity = 1) {
  if (!isPowerOfTwo(capacity) || capacity < min_capacity || capacity > (std::size_t{1} << 30))
    throw ConfigError(std::string(what) + ": capacity " + std::to_string(capacity) +
                      " is not a power of two in " + std::to_string(min_capacity) + "..2^30");
}

}  // namespace ldsm::concurrency
