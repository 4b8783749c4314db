// A bounded single-producer / single-consumer ring (Lamport queue). One thread pushes, one thread
// pops; neither ever blocks or allocates. The capacity is a power of two fixed at construction.
//
// Indices are free-running 64-bit counters (slot = index & mask); `tail_` is written only by the
// producer, `head_` only by the consumer, each on its own cache line together with the owner's
// cached copy of the other index, so that a push or a pop touches the other side's line only
// when the ring looks full or empty. The producer publishes a slot with a release store of
// `tail_` after writing it; the consumer's acquire load of `tail_` makes the slot visible, and
// symmetrically for `head_` when a slot is handed back.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <utility>

#include "concurrency/ring_common.h"

namespace ldsm::concurrency {

template <typename T>
class SpscRing {
 public:
  /// `capacity` must be a power of two (ldsm::ConfigError otherwise). All slots are
  /// default-constructed here; push and pop never allocate.
  explicit SpscRing(std::size_t capacity)
      : mask_((checkRingCapacity(capacity, "SpscRing"), capacity - 1)),
        slots_(std::make_unique<T[]>(capacity)) {}
  SpscRing(const SpscRing&) = delete;
  SpscRing& operator=(const SpscRing&) = delete;

  std::size_t capacity() const { return mask_ + 1; }

  /// Producer only. Stores `value` and returns true, or returns false (value untouched) when the
  /// ring is full.
  template <typename U>
  bool tryPush(U&& value) {
    const std::uint64_t tail = producer_.tail.load(std::memory_order_relaxed);
    if (tail - producer_.head_cache > mask_) {
      producer_.head_cache = consumer_.head.load(std::memory_order_acquire);
      if (tail - producer_.head_cache > mask_) return false;
    }
    slots_[tail & mask_] = std::forward<U>(value);
    producer_.tail.store(tail + 1, std::memory_order_release);
    return true;
  }

  /// Consumer only. Moves the oldest element into `out` and returns true, or returns false when
  /// the ring is empty.
  bool tryPop(T& out) {
    const std::uint64_t head = consumer_.head.load(std::memory_order_relaxed);
    if (head == consumer_.tail_cache) {
      consumer_.tail_cache = producer_.tail.load(std::memory_order_acquire);
      if (head == consumer_.tail_cache) return false;
    }
    out = std::move(slots_[head & mask_]);
    consumer_.head.store(head + 1, std::memory_order_release);
    return true;
  }

  /// Number of queued elements. Exact from the producer or the consumer thread when the other
  /// side is idle; a snapshot in 0..capacity() otherwise (any thread may call it).
  std::size_t size() const {
    const std::uint64_t head = consumer_.head.load(std::memory_order_acquire);
    const std::uint64_t tail = producer_.tail.load(std::memory_order_acquire);
    const std::uint64_t n = tail >= head ? tail - head : 0;
    return n > mask_ ? mask_ + 1 : static_cast<std::size_t>(n);
  }
  bool empty() const { return size() == 0; }

 private:
  struct alignas(kCacheLine) ProducerSide {
    std::atomic<std::uint64_t> tail{0};  ///< next index to write
    std::uint64_t head_cache = 0;        ///< the producer's last view of head
  };
  struct alignas(kCacheLine) ConsumerSide {
    std::atomic<std::uint64_t> head{0};  ///< next index to read
    std::uint64_t tail_cache = 0;        ///< the consumer's last view of tail
  };

  const std::uint64_t mask_;
  std::unique_ptr<T[]> slots_;
  ProducerSide producer_;
  ConsumerSide consumer_;
};

}  // namespace ldsm::concurrency
