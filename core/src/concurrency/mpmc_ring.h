// A bounded multi-producer / multi-consumer ring (D. Vyukov's sequence-per-slot scheme), used as
// the free list of the FramePool: buffers are returned by the consumer that processed them and by
// the producer that dropped them. Lock-free, no allocation after construction.
//
// For the element with free-running index i in slot i & mask: seq == i means free for element i,
// seq == i + 1 means element i stored, seq == i + capacity means taken (free for i + capacity).
// Producers claim an index by compare-exchange on `tail_`, consumers on `head_`; the claimed slot
// is then owned exclusively until its seq is released.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <utility>

#include "concurrency/ring_common.h"

namespace ldsm::concurrency {

template <typename T>
class MpmcRing {
 public:
  /// `capacity` must be a power of two >= 2 (ldsm::ConfigError otherwise).
  explicit MpmcRing(std::size_t capacity)
      : mask_((checkRingCapacity(capacity, "MpmcRing", 2), capacity - 1)),
        slots_(std::make_unique<Slot[]>(capacity)) {
    for (std::size_t i = 0; i < capacity; ++i) slots_[i].seq.store(i, std::memory_order_relaxed);
  }
  MpmcRing(const MpmcRing&) = delete;
  MpmcRing& operator=(const MpmcRing&) = delete;

  std::size_t capacity() const { return mask_ + 1; }

  /// Any thread. Stores `value` and returns true, or returns false (value untouched) when full.
  template <typename U>
  bool tryPush(U&& value) {
    std::uint64_t tail = tail_.load(std::memory_order_relaxed);
    for (;;) {
      Slot& slot = slots_[tail & mask_];
      const auto diff = static_cast<std::int64_t>(slot.seq.load(std::memory_order_acquire) - tail);
      if (diff == 0) {
        if (tail_.compare_exchange_weak(tail, tail + 1, std::memory_order_relaxed)) {
          slot.value = std::forward<U>(value);
          slot.seq.store(tail + 1, std::memory_order_release);
          return true;
        }
      } else if (diff < 0) {
        return false;
      } else {
        tail = tail_.load(std::memory_order_relaxed);
      }
    }
  }

  /// Any thread. Moves the oldest element into `out` and returns true, or returns false when
  /// empty. Like every ring of this kind it also returns false while the oldest slot is claimed
  /// by a push that has not finished writing it, even if later pushes have finished; size() then
  /// counts the claimed slot, so `size() > 0` after a failed pop means "retry in a moment".
  bool tryPop(T& out) {
    std::uint64_t head = head_.load(std::memory_order_relaxed);
    for (;;) {
      Slot& slot = slots_[head & mask_];
      const auto diff =
          static_cast<std::int64_t>(slot.seq.load(std::memory_order_acquire) - (head + 1));
      if (diff == 0) {
        if (head_.compare_exchange_weak(head, head + 1, std::memory_order_relaxed)) {
          out = std::move(slot.value);
          slot.seq.store(head + mask_ + 1, std::memory_order_release);
          return true;
        }
      } else if (diff < 0) {
        return false;
      } else {
        head = head_.load(std::memory_order_relaxed);
      }
    }
  }

  /// Number of elements, including pushes in progress: a snapshot in 0..capacity().
  std::size_t size() const {
    const std::uint64_t head = head_.load(std::memory_order_acquire);
    const std::uint64_t tail = tail_.load(std::memory_order_acquire);
    const std::uint64_t n = tail >= head ? tail - head : 0;
    return n > mask_ ? mask_ + 1 : static_cast<std::size_t>(n);
  }

 private:
  struct Slot {
    std::atomic<std::uint64_t> seq{0};
    T value{};
  };

  const std::uint64_t mask_;
  std::unique_ptr<Slot[]> slots_;
  alignas(kCacheLine) std::atomic<std::uint64_t> tail_{0};
  alignas(kCacheLine) std::atomic<std::uint64_t> head_{0};
};

}  // namespace ldsm::concurrency
