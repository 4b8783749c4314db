// Waiting without a lock: a short busy spin with the CPU's pause hint, then yielding the core, then
// short sleeps, so that a thread waiting on a ring costs little when the wait is long.
#pragma once

#include <chrono>
#include <thread>

namespace ldsm::concurrency {

/// Tells the CPU that this is a spin-wait loop (saves power, frees the sibling hyper-thread).
inline void cpuRelax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__) || (defined(__arm__) && defined(__ARM_ARCH) && __ARM_ARCH >= 7)
  asm volatile("yield" ::: "memory");
#endif
}

/// One waiter's escalating back-off. Create one per wait; call pause() after each failed attempt.
class Backoff {
 public:
  static constexpr int kSpins = 64;            ///< pause-hint iterations first
  static constexpr int kYields = kSpins + 64;  ///< then yields, then sleeps
  static constexpr auto kSleep = std::chrono::microseconds(50);

  void pause() {
    if (count_ < kSpins) {
      cpuRelax();
    } else if (count_ < kYields) {
      std::this_thread::yield();
    } else {
      std::this_thread::sleep_for(kSleep);
    }
    if (count_ < kYields) ++count_;
  }
  void reset() { count_ = 0; }

 private:
  int count_ = 0;
};

}  // namespace ldsm::concurrency
