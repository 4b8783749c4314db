// The heap policy of ldsm's executables: image-sized blocks go back to the system when freed.
#include "ldsm/drivers/allocator_policy.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

// AddressSanitizer replaces the C library's allocator with its own: its mallopt() refuses every
// setting and its mallinfo2() does not count glibc's mapped blocks (scripts/sanitize.sh address).
#if defined(__SANITIZE_ADDRESS__)
#define LDSM_TEST_ASAN_ALLOCATOR 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define LDSM_TEST_ASAN_ALLOCATOR 1
#endif
#endif

namespace ldsm::drivers {
namespace {

#if defined(LDSM_TEST_ASAN_ALLOCATOR)
// Under AddressSanitizer the policy cannot be set, and says so (nothing changes).
TEST(AllocatorPolicy, SaysItWasRefusedWhereTheAllocatorIsNotGlibcs) {
  EXPECT_FALSE(setHeapPolicy());
  EXPECT_FALSE(setHeapPolicy(kMmapThresholdBytes));
}
#elif defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
/// Bytes in blocks the C library mapped on their own (freed: given back to the system).
std::size_t mappedBytes() {
  return mallinfo2().hblkhd;
}

// glibc's default raises its mmap threshold to the largest mapped block freed, so that after a
// 4 MB block was freed a 512 KB one comes from the heap (and stays there when freed); with the
// policy the threshold stays at 256 KiB.
TEST(AllocatorPolicy, ImageSizedBlocksStayMappedAfterALargerOneWasFreed) {
  ASSERT_TRUE(setHeapPolicy());
  const auto touch = [](void* p, std::size_t n) {
    ASSERT_NE(p, nullptr);
    std::memset(p, 1, n);
  };
  void* large = std::malloc(4 << 20);
  touch(large, 4 << 20);
  std::free(large);
  const std::size_t before = mappedBytes();
  constexpr std::size_t kBlock = 512 << 10;
  void* block = std::malloc(kBlock);
  touch(block, kBlock);
  EXPECT_GE(mappedBytes(), before + kBlock);
  std::free(block);
  EXPECT_EQ(mappedBytes(), before);
  // Below the threshold: from the heap as before.
  void* small = std::malloc(64 << 10);
  touch(small, 64 << 10);
  EXPECT_EQ(mappedBytes(), before);
  std::free(small);
}

TEST(AllocatorPolicy, RefusesAThresholdGlibcDoesNotTake) {
  EXPECT_FALSE(setHeapPolicy(std::size_t{1} << 40));
  EXPECT_TRUE(setHeapPolicy(kMmapThresholdBytes));
}
#else
TEST(AllocatorPolicy, DoesNothingWithoutGlibc) {
  EXPECT_FALSE(setHeapPolicy());
}
#endif

}  // namespace
}  // namespace ldsm::drivers
