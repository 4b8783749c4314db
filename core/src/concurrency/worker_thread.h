// A background thread that sleeps until woken and then runs a "drain what is pending" function,
// optionally at the lowest scheduling priority (SCHED_IDLE, else nice 19), so that it only uses
// CPU time the tracking and mapping threads leave idle. Waking never blocks and never allocates
// (a POSIX semaphore post), so the producer can be a real-time-ish thread.
#pragma once

#include <semaphore.h>

#include <atomic>
#include <functional>
#include <thread>

namespace ldsm::concurrency {

/// Scheduling class of the worker thread.
enum class WorkerPriority {
  kNormal,  ///< inherit the creating thread's policy and nice value
  kLowest,  ///< SCHED_IDLE and nice 19 where permitted (logged once when neither is)
};

/// Lowers the calling thread's priority: SCHED_IDLE, then nice 19 for this thread. Returns true
/// when at least one of them took effect.
bool lowerCurrentThreadPriority();

class WorkerThread {
 public:
  /// Starts the thread. After every wake-up it calls `drain` (in the worker thread), which must
  /// process everything pending and return; `stopping()` tells it to hurry.
  WorkerThread(std::function<void()> drain, WorkerPriority priority);
  ~WorkerThread();
  WorkerThread(const WorkerThread&) = delete;
  WorkerThread& operator=(const WorkerThread&) = delete;

  /// Any thread: makes the worker run `drain` (again). Lock-free, never blocks.
  void wake();
  /// Raises the stop flag, wakes the worker and joins it (idempotent; the destructor calls it).
  void stop();
  bool stopping() const { return stop_.load(std::memory_order_acquire); }
  /// The thread, e.g. to pin it to a CPU.
  std::thread::native_handle_type nativeHandle() { return thread_.native_handle(); }

 private:
  void run(WorkerPriority priority);

  std::function<void()> drain_;
  sem_t wakeups_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

/// Logs (once per call) that a background job failed; used by BackgroundTask so that a failing
/// job is reported and skipped, never propagated into the odometry.
void logBackgroundJobFailure(const char* what);

}  // namespace ldsm::concurrency
