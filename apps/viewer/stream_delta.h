// Bookkeeping of the prefix deltas (wire_format.h): where consecutive versions of an array first
// differ, and how much of it a page holds.
#pragma once

#include <cstddef>
#include <vector>

namespace ldsm::viewer {

/// The first element (of `stride` floats) at which `a` and `b` differ bit for bit; the shorter
/// length when one is a prefix of the other.
std::size_t firstDifference(const std::vector<float>& a, const std::vector<float>& b, int stride);

/// What one page holds of one array: `have` elements, of which the first `valid` still equal the
/// publisher's newest version.
struct PageStream {
  std::size_t have = 0;
  std::size_t valid = 0;
  /// A new version first differs from the previous one at `difference`.
  void changedFrom(std::size_t difference) {
    if (difference < valid) valid = difference;
  }
  /// The page received the whole array (`total` elements).
  void sent(std::size_t total) { have = valid = total; }
};

}  // namespace ldsm::viewer
