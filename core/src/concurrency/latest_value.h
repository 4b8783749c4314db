// The latest value of something one thread produces and one other thread reads (the latest
// tracked pose for the application), without locks and without allocation: a triple buffer.
//
// Three copies of T: the writer owns one (back), the reader owns one (front), and the third
// (middle) is exchanged atomically together with a "fresh" bit. publish() writes the back copy and
// swaps it into the middle; the reader swaps the middle into its front only when it is fresh.
// Neither side ever waits for the other, a reader never sees a half-written value, and T may be
// any copy-assignable type (Eigen types included). One writer thread and one reader thread.
#pragma once

#include <atomic>
#include <cstdint>
#include <utility>

#include "concurrency/ring_common.h"

namespace ldsm::concurrency {

template <typename T>
class LatestValue {
 public:
  LatestValue() = default;
  LatestValue(const LatestValue&) = delete;
  LatestValue& operator=(const LatestValue&) = delete;

  /// Writer only. Makes `value` the latest value.
  template <typename U>
  void publish(U&& value) {
    buffers_[writer_.back] = std::forward<U>(value);
    const std::uint8_t previous = middle_.exchange(static_cast<std::uint8_t>(writer_.back | kFresh),
                                                   std::memory_order_acq_rel);
    writer_.back = previous & kIndexMask;
  }

  /// Reader only. Copies the latest value into `out` and returns true when one was published
  /// since the previous call that returned true; returns false otherwise (`out` untouched).
  bool readNew(T& out) {
    if (!takeFresh()) return false;
    out = buffers_[reader_.front];
    return true;
  }

  /// Reader only. Copies the latest value published so far into `out`; returns false when none
  /// has been published yet (`out` untouched).
  bool readLatest(T& out) {
    takeFresh();
    if (!reader_.has_value) return false;
    out = buffers_[reader_.front];
    return true;
  }

 private:
  static constexpr std::uint8_t kIndexMask = 0x3;
  static constexpr std::uint8_t kFresh = 0x4;

  bool takeFresh() {
    if ((middle_.load(std::memory_order_relaxed) & kFresh) == 0) return false;
    const std::uint8_t previous = middle_.exchange(reader_.front, std::memory_order_acq_rel);
    reader_.front = previous & kIndexMask;
    reader_.has_value = true;
    return true;
  }

  struct alignas(kCacheLine) WriterSide {
    std::uint8_t back = 0;
  };
  struct alignas(kCacheLine) ReaderSide {
    std::uint8_t front = 1;
    bool has_value = false;
  };

  T buffers_[3]{};
  WriterSide writer_;
  ReaderSide reader_;
  alignas(kCacheLine) std::atomic<std::uint8_t> middle_{2};
};

}  // namespace ldsm::concurrency
