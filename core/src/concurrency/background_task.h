// A background task over a job queue, with one code path for both modes: a producer submits jobs
// through a bounded lock-free SPSC ring; a worker thread (at the given priority) runs the
// plugged-in "process one job" callable and publishes its results in a mailbox the consumer
// polls at a safe point. In kInline mode (deterministic runs) submit() runs the very same
// processing synchronously, so results do not depend on thread timing. The mapping stage (a
// window change per job) and loop closure (a keyframe per job, corrections as results) run on it.
//
// Threads: submit() from one producer thread; tryTakeResults()/takeResults() from one consumer
// thread; stop()/waitIdle()/finish() from the owner. The processor runs in the worker thread only
// (kThreaded) or in the submitting thread (kInline), never concurrently with itself.
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <utility>
#include <vector>

#include "concurrency/backoff.h"
#include "concurrency/result_mailbox.h"
#include "concurrency/ring_common.h"
#include "concurrency/spsc_ring.h"
#include "concurrency/worker_thread.h"
#include "ldsm/error.h"

namespace ldsm::concurrency {

enum class TaskMode { kThreaded, kInline };

struct TaskOptions {
  TaskMode mode = TaskMode::kThreaded;
  std::size_t queue_capacity = 32;  ///< rounded up to a power of two
  /// A full ring: false drops the job (and counts it), true makes submit() wait for room.
  bool wait_when_full = false;
  WorkerPriority priority = WorkerPriority::kLowest;
};

template <typename Job, typename Result>
class BackgroundTask {
 public:
  /// Processes one job; returns a result to publish or nothing. `abort` becomes true on stop():
  /// long computations (pose-graph solves) should poll it. Exceptions are logged and the job is
  /// skipped: a failing job never reaches the producer (a failing loop closure never stops the
  /// odometry).
  using Processor = std::function<std::optional<Result>(Job& job, const std::atomic<bool>& abort)>;

  /// Job must be default-constructible and movable. Throws ConfigError without a processor.
  BackgroundTask(Processor processor, const TaskOptions& options)
      : processor_(std::move(processor)),
        mode_(options.mode),
        wait_when_full_(options.wait_when_full),
        queue_(concurrency::nextPowerOfTwo(std::max<std::size_t>(1, options.queue_capacity))) {
    if (!processor_) throw ConfigError("background task: no processor given");
    if (mode_ == TaskMode::kThreaded) {
      worker_ = std::make_unique<WorkerThread>([this] { drain(); }, options.priority);
    }
  }
  ~BackgroundTask() { stop(); }
  BackgroundTask(const BackgroundTask&) = delete;
  BackgroundTask& operator=(const BackgroundTask&) = delete;

  /// Producer: queues a job (kThreaded; never allocates beyond what Job's move does) or
  /// processes it now (kInline). When the ring is full it waits for room (wait_when_full) or
  /// drops the job, counts it and returns false. False also when the task is stopped.
  bool submit(Job job) {
    if (abort_.load(std::memory_order_acquire)) return false;
    submitted_.fetch_add(1, std::memory_order_acq_rel);
    if (mode_ == TaskMode::kInline) {
      process(job);
      return true;
    }
    bool pushed = queue_.tryPush(std::move(job));
    for (Backoff backoff; !pushed && wait_when_full_ && !aborted(); backoff.pause())
      pushed = queue_.tryPush(std::move(job));
    if (!pushed) {
      submitted_.fetch_sub(1, std::memory_order_acq_rel);
      if (!aborted()) dropped_.fetch_add(1, std::memory_order_relaxed);
      return false;
    }
    worker_->wake();
    return true;
  }

  /// The worker thread (kThreaded), e.g. to pin it to a CPU; nothing in kInline mode.
  std::optional<std::thread::native_handle_type> workerHandle() {
    if (!worker_) return std::nullopt;
    return worker_->nativeHandle();
  }

  /// Jobs queued and not yet taken by the worker (a snapshot; 0 in kInline mode).
  std::size_t backlog() const { return queue_.size(); }

  /// Mapper at a safe point: the results published so far; never blocks (may return nothing
  /// while the worker is posting, then try again later).
  std::vector<Result> tryTakeResults() { return mailbox_.tryTakeAll(); }
  /// Blocking variant (end of a sequence, deterministic mode).
  std::vector<Result> takeResults() { return mailbox_.takeAll(); }

  /// Waits until every submitted job has been processed; false on timeout or when stopped with
  /// jobs pending.
  bool waitIdle(std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(idle_mutex_);
    idle_cv_.wait_for(lock, timeout, [this] { return idle() || aborted(); });
    return idle();
  }

  /// End of a run, bounded: waits up to `timeout` for every submitted job; if some are still
  /// unprocessed then, stops the task (stop(): the running job is asked to abort, the queued ones
  /// are dropped). Returns unfinished(): 0 when every job was processed (the task keeps running),
  /// else how many were not when it was stopped. After a non-zero return the worker has been
  /// joined, so the processor's state may be read from the calling thread.
  std::uint64_t finish(std::chrono::milliseconds timeout) {
    if (!aborted() && waitIdle(timeout)) return 0;
    stop();
    return unfinished();
  }

  /// Every submitted job has been processed (a snapshot).
  bool idle() const { return processed() >= submitted(); }
  /// stop() was called (by finish() or the owner): submit() refuses every job.
  bool stopped() const { return aborted(); }
  /// Raises the abort flag (the running job should return soon), joins the worker and drops what
  /// is still queued. Idempotent; the destructor calls it.
  void stop() {
    const bool first = !abort_.exchange(true, std::memory_order_acq_rel);
    if (worker_) worker_->stop();
    idle_cv_.notify_all();
    if (!first) return;
    // Counted once the worker is joined: a job that completed meanwhile is not unfinished, the
    // one the abort cut short is.
    const std::uint64_t done = processed(), all = submitted();
    unfinished_.store((all > done ? all - done : 0) + (cut_short_.load() ? 1 : 0),
                      std::memory_order_relaxed);
  }

  TaskMode mode() const { return mode_; }
  std::uint64_t submitted() const { return submitted_.load(std::memory_order_acquire); }
  std::uint64_t processed() const { return processed_.load(std::memory_order_acquire); }
  std::uint64_t dropped() const { return dropped_.load(std::memory_order_relaxed); }
  std::uint64_t failed() const { return failed_.load(std::memory_order_relaxed); }
  /// Jobs submitted and not processed to the end when stop() was first called: those dropped
  /// from the queue and the one running then (asked to abort, it may have returned early); 0
  /// while the task runs.
  std::uint64_t unfinished() const { return unfinished_.load(std::memory_order_relaxed); }

 private:
  bool aborted() const { return abort_.load(std::memory_order_acquire); }

  // Worker thread: everything queued, unless stopping.
  void drain() {
    Job job;
    while (!aborted() && queue_.tryPop(job)) {
      process(job);
      job = Job();  // release what the job holds before sleeping
    }
  }

  // The one code path of both modes.
  void process(Job& job) {
    std::optional<Result> result;
    try {
      result = processor_(job, abort_);
    } catch (const std::exception& e) {
      failed_.fetch_add(1, std::memory_order_relaxed);
      logBackgroundJobFailure(e.what());
    } catch (...) {
      failed_.fetch_add(1, std::memory_order_relaxed);
      logBackgroundJobFailure("unknown exception");
    }
    if (aborted()) cut_short_.store(true);  // it may have returned early (the abort flag)
    if (result) mailbox_.post(std::move(*result));
    {
      const std::lock_guard<std::mutex> lock(idle_mutex_);
      processed_.fetch_add(1, std::memory_order_acq_rel);
    }
    idle_cv_.notify_all();
  }

  Processor processor_;
  const TaskMode mode_;
  const bool wait_when_full_;
  concurrency::SpscRing<Job> queue_;
  ResultMailbox<Result> mailbox_;
  std::atomic<bool> abort_{false};
  std::atomic<bool> cut_short_{false};  ///< a job was running when the abort came
  std::atomic<std::uint64_t> submitted_{0}, processed_{0}, dropped_{0}, failed_{0}, unfinished_{0};
  std::mutex idle_mutex_;
  std::condition_variable idle_cv_;
  std::unique_ptr<WorkerThread> worker_;  // last: stopped before the members it uses go away
};

}  // namespace ldsm::concurrency
