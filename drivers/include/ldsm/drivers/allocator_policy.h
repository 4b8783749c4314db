// The heap policy of a long-running ldsm process (the `ldsm` tool, the benchmarks; a robot's own
// program can call it too). Process-wide, so it lives here and not in core.
//
// glibc serves large blocks with mmap and gives them back to the system when they are freed, but
// it raises that threshold to the largest such block freed so far (up to 32 MB), after which image
// sized buffers (a keyframe's pyramid planes, decoded images, the window optimisation's
// temporaries) come from the heap and stay there, scattered between long-lived allocations, after
// they are freed. kitti00_200: peak resident memory 143 MB with glibc's default, 115 MB with the
// threshold fixed at 256 KiB (docs/engine.md, "Memory").
#pragma once

#include <cstddef>

namespace ldsm::drivers {

/// The default mmap threshold of setHeapPolicy().
constexpr std::size_t kMmapThresholdBytes = 256 * 1024;

/// Fixes the C library's mmap threshold at `mmap_threshold` bytes (blocks at least this large are
/// mapped on their own and returned to the system when freed). Returns false where the C library
/// has no such setting (not glibc), or when the allocator refused the value (too large for glibc;
/// any value under AddressSanitizer, whose allocator replaces glibc's); nothing changes then.
bool setHeapPolicy(std::size_t mmap_threshold = kMmapThresholdBytes);

}  // namespace ldsm::drivers
