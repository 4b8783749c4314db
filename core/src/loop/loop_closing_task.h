// The loop-closing background task: the mapper submits every new keyframe (a Job) through a
// bounded lock-free SPSC ring; a worker thread at the lowest priority runs the plugged-in
// "process one keyframe" callable (detection + verification + pose graph) and publishes its
// results (LoopCorrection: corrected keyframe poses) in a mailbox the mapper polls at a safe
// point. In kInline mode (deterministic runs) submit() runs the very same processing
// synchronously, so results do not depend on thread timing.
//
// Threads: submit() from one producer thread (the mapper); tryTakeResults()/takeResults() from one
// consumer thread; stop()/waitIdle() from the owner. The processor runs in the worker thread only
// (kThreaded) or in the submitting thread (kInline), never concurrently with itself.
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <utility>
#include <vector>

#include "ldsm/error.h"
#include "ldsm/math/sim3.h"
#include "loop/result_mailbox.h"
#include "loop/worker_thread.h"
#include "pipeline/ring_common.h"
#include "pipeline/spsc_ring.h"

namespace ldsm::loop {

/// What the loop closer hands to the mapper after a closed loop.
struct LoopCorrection {
  int current_keyframe_id = -1;
  int candidate_keyframe_id = -1;
  int inliers = 0;
  double scale = 1.0;  ///< of S_current_candidate
  /// Corrected world-from-camera poses by keyframe id (the keyframes outside the active window;
  /// the mapper moves their points with them and must not overwrite the active window).
  std::map<int, Sim3d> S_world_camera;  ///< empty when the drift was not significant
  double drift_chi2 = 0.0;              ///< see LoopClosureEvent::drift_chi2
  double time_ms = 0.0;
};

enum class LoopTaskMode { kThreaded, kInline };

struct LoopTaskOptions {
  LoopTaskMode mode = LoopTaskMode::kThreaded;
  std::size_t queue_capacity = 32;  ///< rounded up to a power of two; full ring: job dropped
  WorkerPriority priority = WorkerPriority::kLowest;
};

template <typename Job, typename Result = LoopCorrection>
class LoopClosingTask {
 public:
  /// Processes one job; returns a result to publish or nothing. `abort` becomes true on stop():
  /// long computations (pose-graph solves) should poll it. Exceptions are logged and the job is
  /// skipped: a failing loop closure never reaches the odometry.
  using Processor = std::function<std::optional<Result>(Job& job, const std::atomic<bool>& abort)>;

  /// Job must be default-constructible and movable. Throws ConfigError without a processor.
  LoopClosingTask(Processor processor, const LoopTaskOptions& options)
      : processor_(std::move(processor)),
        mode_(options.mode),
        queue_(pipeline::nextPowerOfTwo(std::max<std::size_t>(1, options.queue_capacity))) {
    if (!processor_) throw ConfigError("loop closing task: no processor given");
    if (mode_ == LoopTaskMode::kThreaded) {
      worker_ = std::make_unique<WorkerThread>([this] { drain(); }, options.priority);
    }
  }
  ~LoopClosingTask() { stop(); }
  LoopClosingTask(const LoopClosingTask&) = delete;
  LoopClosingTask& operator=(const LoopClosingTask&) = delete;

  /// Producer: queues a keyframe (kThreaded; never blocks, never allocates beyond what Job's move
  /// does) or processes it now (kInline). False when the ring is full (the job is dropped and
  /// counted) or the task is stopped.
  bool submit(Job job) {
    if (abort_.load(std::memory_order_acquire)) return false;
    submitted_.fetch_add(1, std::memory_order_acq_rel);
    if (mode_ == LoopTaskMode::kInline) {
      process(job);
      return true;
    }
    if (!queue_.tryPush(std::move(job))) {
      submitted_.fetch_sub(1, std::memory_order_acq_rel);
      dropped_.fetch_add(1, std::memory_order_relaxed);
      return false;
    }
    worker_->wake();
    return true;
  }

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

  /// Raises the abort flag (the running job should return soon), joins the worker and drops what
  /// is still queued. Idempotent; the destructor calls it.
  void stop() {
    abort_.store(true, std::memory_order_release);
    if (worker_) worker_->stop();
    idle_cv_.notify_all();
  }

  LoopTaskMode mode() const { return mode_; }
  std::uint64_t submitted() const { return submitted_.load(std::memory_order_acquire); }
  std::uint64_t processed() const { return processed_.load(std::memory_order_acquire); }
  std::uint64_t dropped() const { return dropped_.load(std::memory_order_relaxed); }
  std::uint64_t failed() const { return failed_.load(std::memory_order_relaxed); }

 private:
  bool aborted() const { return abort_.load(std::memory_order_acquire); }
  bool idle() const { return processed() >= submitted(); }

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
    if (result) mailbox_.post(std::move(*result));
    {
      const std::lock_guard<std::mutex> lock(idle_mutex_);
      processed_.fetch_add(1, std::memory_order_acq_rel);
    }
    idle_cv_.notify_all();
  }

  Processor processor_;
  const LoopTaskMode mode_;
  pipeline::SpscRing<Job> queue_;
  ResultMailbox<Result> mailbox_;
  std::atomic<bool> abort_{false};
  std::atomic<std::uint64_t> submitted_{0}, processed_{0}, dropped_{0}, failed_{0};
  std::mutex idle_mutex_;
  std::condition_variable idle_cv_;
  std::unique_ptr<WorkerThread> worker_;  // last: stopped before the members it uses go away
};

}  // namespace ldsm::loop
