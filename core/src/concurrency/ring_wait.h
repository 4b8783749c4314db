// Waiting pushes and pops over the rings for the offline (lossless) mode: the producer waits while
// the ring is full, the consumer while it is empty, both with an escalating Backoff, until the
// `stop` flag is raised. Works with SpscRing, DropOldestRing and MpmcRing. pushWithPolicy()
// selects offline (wait) or live (drop the oldest) behaviour at run time.
#pragma once

#include <atomic>
#include <utility>

#include "concurrency/backoff.h"
#include "concurrency/drop_oldest_ring.h"

namespace ldsm::concurrency {

/// Pushes `value`, waiting while the ring is full. Returns false, without pushing, when `stop`
/// is raised before there is room.
template <typename Ring, typename U>
bool pushWaiting(Ring& ring, U&& value, const std::atomic<bool>& stop) {
  for (Backoff backoff;; backoff.pause()) {
    if (ring.tryPush(std::forward<U>(value))) return true;  // moved from only on success
    if (stop.load(std::memory_order_acquire)) return false;
  }
}

/// Pops into `out`, waiting while the ring is empty. When `stop` is raised, what was pushed before
/// it is still returned; returns false once the ring is empty and `stop` is raised (the producer
/// raises it after its last push: end of stream).
template <typename Ring, typename T>
bool popWaiting(Ring& ring, T& out, const std::atomic<bool>& stop) {
  for (Backoff backoff;; backoff.pause()) {
    if (ring.tryPop(out)) return true;
    if (stop.load(std::memory_order_acquire)) return ring.tryPop(out);
  }
}

/// What a full ring does to the producer: wait (offline, lossless) or drop the oldest queued
/// element (live, counted in DropOldestRing::droppedCount()).
enum class OverflowPolicy { Wait, DropOldest };

enum class PushOutcome {
  Pushed,                ///< stored, nothing dropped
  PushedDroppingOldest,  ///< stored after moving the oldest element into `dropped`
  Stopped,               ///< `stop` was raised while waiting: not stored
};

/// Producer only. Pushes `value` with the given policy; with DropOldest never waits (beyond the
/// consumer's copy of one element).
template <typename T, typename U>
PushOutcome pushWithPolicy(DropOldestRing<T>& ring, U&& value, OverflowPolicy policy,
                           const std::atomic<bool>& stop, T& dropped) {
  if (policy == OverflowPolicy::DropOldest)
    return ring.pushDroppingOldest(std::forward<U>(value), dropped)
               ? PushOutcome::PushedDroppingOldest
               : PushOutcome::Pushed;
  return pushWaiting(ring, std::forward<U>(value), stop) ? PushOutcome::Pushed
                                                         : PushOutcome::Stopped;
}

}  // namespace ldsm::concurrency
