// A bounded single-producer / single-consumer ring for live input: when the ring is full the
// PRODUCER may drop the oldest queued element to make room (pushDroppingOldest), so that the
// consumer always works on the most recent frames; drops are counted. tryPush is the ordinary
// non-dropping push (offline mode: the producer waits instead, see ring_wait.h).
//
// Design: every slot carries a sequence number (as in D. Vyukov's bounded queue). For the element
// with free-running index i stored in slot i & mask:
//   seq == i              the slot is free for element i (the producer may write it);
//   seq == i + 1          element i is stored and not yet taken;
//   seq == i + capacity   element i has been taken and the slot is free for element i + capacity.
// The producer alone advances `tail_`. `head_` (index of the oldest element) is advanced by
// compare-exchange, by the consumer when it takes an element and by the producer when it drops
// one, so exactly one of them owns any element: the winner of the exchange. The producer drops
// only element tail - capacity, whose slot is the very slot it wants to write; when it wins the
// exchange it moves the old element out and writes the new one in place, so no element is
// dropped unless the ring is really full. When it loses, the consumer is copying that element
// out and frees the slot a moment later (the producer spins for that short copy, which is why
// elements should be small: an index into a FramePool and a few numbers).
//
// Memory order: element writes are published by the release store of the slot's seq and seen
// through the acquire load of it; taking an element and handing the slot back go through the
// same seq, so every write to a slot happens-after the previous read of it.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <utility>

#include "concurrency/backoff.h"
#include "concurrency/ring_common.h"

namespace ldsm::concurrency {

template <typename T>
class DropOldestRing {
 public:
  /// `capacity` must be a power of two >= 2 (ldsm::ConfigError otherwise). No allocation
  /// afterwards.
  explicit DropOldestRing(std::size_t capacity)
      : mask_((checkRingCapacity(capacity, "DropOldestRing", 2), capacity - 1)),
        slots_(std::make_unique<Slot[]>(capacity)) {
    for (std::size_t i = 0; i < capacity; ++i) slots_[i].seq.store(i, std::memory_order_relaxed);
  }
  DropOldestRing(const DropOldestRing&) = delete;
  DropOldestRing& operator=(const DropOldestRing&) = delete;

  std::size_t capacity() const { return mask_ + 1; }

  /// Producer only. Stores `value` and returns true, or returns false (value untouched) when the
  /// ring is full.
  template <typename U>
  bool tryPush(U&& value) {
    const std::uint64_t tail = tail_.load(std::memory_order_relaxed);
    Slot& slot = slots_[tail & mask_];
    if (slot.seq.load(std::memory_order_acquire) != tail) return false;
    store(slot, tail, std::forward<U>(value));
    return true;
  }

  /// Producer only. Stores `value`; when the ring is full, first removes the oldest element into
  /// `dropped`, counts it and returns true (the caller releases what it refers to). Returns false
  /// when nothing was dropped (`dropped` untouched).
  template <typename U>
  bool pushDroppingOldest(U&& value, T& dropped) {
    const std::uint64_t tail = tail_.load(std::memory_order_relaxed);
    Slot& slot = slots_[tail & mask_];
    for (Backoff backoff;; backoff.pause()) {
      if (slot.seq.load(std::memory_order_acquire) == tail) {
        store(slot, tail, std::forward<U>(value));
        return false;
      }
      // Full: the slot holds element tail - capacity, the oldest. Take it unless the consumer
      // has just taken it (then it hands the slot back after its copy: wait for that).
      std::uint64_t oldest = tail - (mask_ + 1);
      if (head_.compare_exchange_strong(oldest, oldest + 1, std::memory_order_acq_rel,
                                        std::memory_order_relaxed)) {
        dropped = std::move(slot.value);
        store(slot, tail, std::forward<U>(value));
        dropped_.store(dropped_.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
        return true;
      }
    }
  }

  /// Consumer only. Moves the oldest element into `out` and returns true, or returns false when
  /// the ring is empty.
  bool tryPop(T& out) {
    std::uint64_t head = head_.load(std::memory_order_relaxed);
    for (;;) {
      Slot& slot = slots_[head & mask_];
      const auto diff =
          static_cast<std::int64_t>(slot.seq.load(std::memory_order_acquire) - (head + 1));
      if (diff == 0) {
        // Element `head` is there; take it unless the producer drops it first (then `head` is
        // reloaded by the failed exchange and the next element is tried).
        if (head_.compare_exchange_weak(head, head + 1, std::memory_order_acq_rel,
                                        std::memory_order_relaxed)) {
          out = std::move(slot.value);
          slot.seq.store(head + mask_ + 1, std::memory_order_release);
          return true;
        }
      } else if (diff < 0) {
        return false;  // empty: element `head` not written yet
      } else {
        head = head_.load(std::memory_order_relaxed);  // dropped and overwritten meanwhile
      }
    }
  }

  /// Number of queued elements: a snapshot in 0..capacity() (exact when the ring is idle).
  std::size_t size() const {
    const std::uint64_t head = head_.load(std::memory_order_acquire);
    const std::uint64_t tail = tail_.load(std::memory_order_acquire);
    const std::uint64_t n = tail >= head ? tail - head : 0;
    return n > mask_ ? mask_ + 1 : static_cast<std::size_t>(n);
  }
  bool empty() const { return size() == 0; }

  /// Elements dropped by pushDroppingOldest so far (exact once the producer has stopped).
  std::uint64_t droppedCount() const { return dropped_.load(std::memory_order_relaxed); }

 private:
  struct alignas(kCacheLine) Slot {
    std::atomic<std::uint64_t> seq{0};
    T value{};
  };

  template <typename U>
  void store(Slot& slot, std::uint64_t tail, U&& value) {
    slot.value = std::forward<U>(value);
    slot.seq.store(tail + 1, std::memory_order_release);
    tail_.store(tail + 1, std::memory_order_release);
  }

  const std::uint64_t mask_;
  std::unique_ptr<Slot[]> slots_;
  alignas(kCacheLine) std::atomic<std::uint64_t> tail_{0};     ///< producer: next index to write
  alignas(kCacheLine) std::atomic<std::uint64_t> head_{0};     ///< oldest element not yet taken
  alignas(kCacheLine) std::atomic<std::uint64_t> dropped_{0};  ///< written by the producer only
};

}  // namespace ldsm::concurrency
