// Uniform pixel noise for the frames a test replaces (a covered lens, a camera fault): nothing in
// it can be tracked, and the same seed gives the same image on every machine.
#pragma once

#include <cstdint>

#include "ldsm/image.h"

namespace ldsm::test {

/// Fills `image` with uniform 8-bit noise from a linear congruential generator seeded by `seed`.
inline void fillWithNoise(ImageU8& image, std::uint32_t seed) {
  std::uint32_t x = seed * 2654435761u + 1u;
  for (int y = 0; y < image.height(); ++y)
    for (int u = 0; u < image.width(); ++u) {
      x = x * 1664525u + 1013904223u;
      image(u, y) = static_cast<std::uint8_t>(x >> 24);
    }
}

}  // namespace ldsm::test
