// Counts heap allocations made by this test executable: every global operator new (all variants)
// and aligned_alloc (used by ldsm::Image) are replaced in alloc_counter.cpp. Tests in this folder
// use it to prove that hot paths allocate nothing after set-up.
#pragma once

#include <cstddef>

namespace ldsm::test {

/// Number of heap allocations since the program started.
std::size_t allocationCount();

/// Allocations made between construction and count().
class AllocationScope {
 public:
  AllocationScope() : start_(allocationCount()) {}
  std::size_t count() const { return allocationCount() - start_; }

 private:
  std::size_t start_;
};

}  // namespace ldsm::test
