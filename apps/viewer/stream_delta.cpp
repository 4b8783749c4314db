#include "stream_delta.h"

#include <algorithm>
#include <cstring>

namespace ldsm::viewer {

std::size_t firstDifference(const std::vector<float>& a, const std::vector<float>& b, int stride) {
  const auto s = static_cast<std::size_t>(std::max(stride, 1));
  const std::size_t n = std::min(a.size(), b.size()) / s;
  for (std::size_t i = 0; i < n; ++i)
    if (std::memcmp(a.data() + i * s, b.data() + i * s, s * sizeof(float)) != 0) return i;
  return n;
}

}  // namespace ldsm::viewer
