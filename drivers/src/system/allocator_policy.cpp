#include "ldsm/drivers/allocator_policy.h"

#include <climits>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace ldsm::drivers {

bool setHeapPolicy(std::size_t mmap_threshold) {
#if defined(__GLIBC__)
  // glibc caps M_MMAP_THRESHOLD at HEAP_MAX_SIZE / 2 (32 MiB on 64-bit) and mallopt() returns 0
  // for values above it.
  if (mmap_threshold > static_cast<std::size_t>(INT_MAX)) return false;
  return mallopt(M_MMAP_THRESHOLD, static_cast<int>(mmap_threshold)) == 1;
#else
  (void)mmap_threshold;
  return false;
#endif
}

}  // namespace ldsm::drivers
