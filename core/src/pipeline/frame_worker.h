// The System's input stage, with one code path for both modes (like concurrency::BackgroundTask).
// Threaded: submit() copies each frame into a buffer of a FramePool allocated at start-up and
// queues a FrameTicket (buffer index + metadata) in a lock-free DropOldestRing; the tracking
// thread owned here pops tickets in order, runs the handler on the buffer and releases it.
// Nothing is allocated per frame. Inline (deterministic mode): push() runs the handler on the
// caller's thread, on the caller's image, with no pool, queue or thread.
//
//   producer (submit) --FrameTicket, DropOldestRing(queue_capacity)--> tracking thread
//        ^                                                                  |
//        +------------------- FramePool (free buffer indices) <-------------+
//
// Offline (the default) the producer waits while the queue is full, so nothing is lost. Live
// (system.live), it drops the oldest queued frame instead, releases its buffer and counts it, so
// that tracking always works on the newest frames. The pool holds queue_capacity + 2 buffers or
// more (one being filled by the producer, one being tracked), so the producer never waits for a
// buffer in live mode.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <thread>

#include "concurrency/background_task.h"
#include "concurrency/drop_oldest_ring.h"
#include "concurrency/ring_wait.h"
#include "ldsm/system.h"
#include "pipeline/frame_pool.h"

namespace ldsm {

/// Pins `thread` to CPU `cpu`; does nothing for cpu < 0. Returns false and logs a warning naming
/// `what` when the operating system refuses (no such CPU, not permitted, not Linux).
bool pinThreadToCpu(std::thread::native_handle_type thread, int cpu, const char* what);
/// The same for the calling thread.
bool pinCurrentThreadToCpu(int cpu, const char* what);

/// Nanoseconds on std::chrono::steady_clock (the clock of FrameTicket::enqueued_ns).
std::int64_t steadyNowNs();

struct FrameWorkerOptions {
  int pool_size = 6;  ///< frame buffers (>= 4)
  int width = 0;      ///< frame size
  int height = 0;
  bool live = false;  ///< drop the oldest queued frame instead of waiting
  int cpu = -1;       ///< CPU of the tracking thread (-1: any)
  /// kInline: the handler runs inside push() (deterministic mode; the other fields are unused).
  concurrency::TaskMode mode = concurrency::TaskMode::kThreaded;
};

/// Counters of the queue (values, safe to read from any thread).
struct FrameWorkerCounts {
  std::int64_t submitted = 0;  ///< frames pushed
  std::int64_t dropped = 0;    ///< frames dropped from the queue (live mode)
  std::int64_t processed = 0;  ///< frames the handler has finished
  int queue_capacity = 0;      ///< 0 inline
  int max_queue_depth = 0;     ///< after each push
  double mean_queue_depth = 0.0;
};

class FrameWorker {
 public:
  /// Called on the tracking thread for every frame, in order, with the steady_clock time (ns)
  /// at which the frame was pushed. Exceptions are logged and the next frame is processed
  /// (threaded), or reach the caller of push() (inline).
  using Handler = std::function<void(const FrameView&, std::int64_t enqueued_ns)>;

  /// Threaded: allocates the pool and the queue (ldsm::ConfigError for a pool smaller than 4) and
  /// starts the tracking thread. Inline: nothing.
  FrameWorker(Handler handler, const FrameWorkerOptions& options);
  ~FrameWorker();
  FrameWorker(const FrameWorker&) = delete;
  FrameWorker& operator=(const FrameWorker&) = delete;

  /// Producer only (one thread). Copies `frame` (of the pool's size) into a free buffer and
  /// queues it: waits while the queue is full (offline) or drops the oldest queued frame (live).
  /// Inline: runs the handler on `frame` now. Does nothing once stop() was called.
  void push(const FrameView& frame);
  /// Producer only. Waits until every pushed frame has been processed or dropped.
  void drain();
  /// Processes what is queued, then ends the thread.
  void stop();

  FrameWorkerCounts counts() const;
  /// Frames wait in a queue for a thread of their own (threaded mode).
  bool queued() const { return mode_ == concurrency::TaskMode::kThreaded; }
  /// The tracking thread, e.g. to query its CPU affinity.
  std::thread::native_handle_type threadHandle() { return thread_.native_handle(); }

 private:
  void run();
  void acquire(pipeline::FrameTicket& ticket);

  Handler handler_;
  const concurrency::TaskMode mode_;
  std::optional<pipeline::FramePool> pool_;  ///< threaded only
  concurrency::DropOldestRing<pipeline::FrameTicket> queue_;
  concurrency::OverflowPolicy policy_;
  int cpu_;
  std::atomic<bool> stop_{false};
  // Written by the producer only (relaxed; read by counts()).
  std::atomic<std::int64_t> submitted_{0};
  std::atomic<std::int64_t> dropped_{0};
  std::atomic<std::int64_t> depth_sum_{0};
  std::atomic<int> max_depth_{0};
  // Written by the tracking thread only.
  std::atomic<std::int64_t> processed_{0};
  std::thread thread_;
};

}  // namespace ldsm
