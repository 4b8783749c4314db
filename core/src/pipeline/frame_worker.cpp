#include "pipeline/frame_worker.h"

#include <spdlog/spdlog.h>

#if defined(__linux__)
#include <pthread.h>
#include <sched.h>
#endif

#include <algorithm>
#include <chrono>
#include <cstring>
#include <exception>
#include <string>

#include "concurrency/backoff.h"
#include "ldsm/error.h"

namespace ldsm {
namespace {

/// The queue's capacity for a pool of `pool_size` buffers: the largest power of two that leaves
/// one buffer to the producer and one to the tracking thread.
std::size_t queueCapacityFor(int pool_size) {
  if (pool_size < 4)
    throw ConfigError("system.frame_pool_size = " + std::to_string(pool_size) +
                      " is outside the allowed range [4, 1024]");
  std::size_t capacity = 2;
  while (capacity * 2 + 2 <= static_cast<std::size_t>(pool_size)) capacity *= 2;
  return capacity;
}

}  // namespace

std::int64_t steadyNowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

bool pinThreadToCpu(std::thread::native_handle_type thread, int cpu, const char* what) {
  if (cpu < 0) return true;
#if defined(__linux__)
  if (cpu >= CPU_SETSIZE) {
    spdlog::warn("{} thread: cannot pin to CPU {} (beyond {}); it runs on any CPU", what, cpu,
                 CPU_SETSIZE - 1);
    return false;
  }
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  const int err = pthread_setaffinity_np(thread, sizeof(set), &set);
  if (err != 0) {
    spdlog::warn("{} thread: pinning to CPU {} refused ({}); it runs on any CPU", what, cpu,
                 std::strerror(err));
    return false;
  }
  spdlog::debug("{} thread pinned to CPU {}", what, cpu);
  return true;
#else
  (void)thread;
  spdlog::warn("{} thread: CPU affinity is not supported on this system; it runs on any CPU", what);
  return false;
#endif
}

bool pinCurrentThreadToCpu(int cpu, const char* what) {
#if defined(__linux__)
  return pinThreadToCpu(pthread_self(), cpu, what);
#else
  return pinThreadToCpu(std::thread::native_handle_type{}, cpu, what);
#endif
}

FrameWorker::FrameWorker(Handler handler, const FrameWorkerOptions& options)
    : handler_(std::move(handler)),
      mode_(options.mode),
      queue_(queued() ? queueCapacityFor(options.pool_size) : 2),
      policy_(options.live ? concurrency::OverflowPolicy::DropOldest
                           : concurrency::OverflowPolicy::Wait),
      cpu_(options.cpu) {
  if (!queued()) return;
  pool_.emplace(static_cast<std::size_t>(std::max(options.pool_size, 0)), options.width,
                options.height);
  thread_ = std::thread([this] { run(); });
}

FrameWorker::~FrameWorker() {
  stop();
}

void FrameWorker::acquire(pipeline::FrameTicket& ticket) {
  // Live mode never waits here (the pool outnumbers the queue by two); offline the producer
  // waits for the tracking thread to give a buffer back.
  for (concurrency::Backoff backoff; (ticket.buffer = pool_->tryAcquire()) < 0; backoff.pause())
    if (stop_.load(std::memory_order_acquire)) return;
}

void FrameWorker::push(const FrameView& frame) {
  if (stop_.load(std::memory_order_acquire)) return;
  if (!queued()) {
    submitted_.store(submitted_.load(std::memory_order_relaxed) + 1, std::memory_order_release);
    handler_(frame, steadyNowNs());
    processed_.store(processed_.load(std::memory_order_relaxed) + 1, std::memory_order_release);
    return;
  }
  pipeline::FrameTicket ticket;
  ticket.enqueued_ns = steadyNowNs();
  acquire(ticket);
  if (ticket.buffer < 0) return;  // stopped while waiting
  ImageU8& image = pool_->image(ticket.buffer);
  image.copyFrom(frame.image);  // same size as the pool's buffers: no allocation
  const std::int64_t index = submitted_.load(std::memory_order_relaxed);
  ticket.index = index;
  ticket.timestamp = frame.timestamp;
  ticket.exposure_ms = frame.exposure_ms;
  submitted_.store(index + 1, std::memory_order_release);
  pipeline::FrameTicket dropped;
  switch (concurrency::pushWithPolicy(queue_, ticket, policy_, stop_, dropped)) {
    case concurrency::PushOutcome::Pushed:
      break;
    case concurrency::PushOutcome::PushedDroppingOldest:
      pool_->release(dropped.buffer);
      dropped_.store(dropped_.load(std::memory_order_relaxed) + 1, std::memory_order_release);
      break;
    case concurrency::PushOutcome::Stopped:
      pool_->release(ticket.buffer);
      submitted_.store(index, std::memory_order_release);
      return;
  }
  const int depth = static_cast<int>(queue_.size());
  depth_sum_.store(depth_sum_.load(std::memory_order_relaxed) + depth, std::memory_order_relaxed);
  if (depth > max_depth_.load(std::memory_order_relaxed))
    max_depth_.store(depth, std::memory_order_relaxed);
}

void FrameWorker::drain() {
  for (concurrency::Backoff backoff;; backoff.pause()) {
    const std::int64_t done =
        processed_.load(std::memory_order_acquire) + dropped_.load(std::memory_order_acquire);
    if (done >= submitted_.load(std::memory_order_acquire)) return;
    if (!thread_.joinable()) return;
  }
}

void FrameWorker::stop() {
  stop_.store(true, std::memory_order_release);
  if (thread_.joinable()) thread_.join();
}

FrameWorkerCounts FrameWorker::counts() const {
  FrameWorkerCounts c;
  c.submitted = submitted_.load(std::memory_order_acquire);
  c.dropped = dropped_.load(std::memory_order_acquire);
  c.processed = processed_.load(std::memory_order_acquire);
  c.queue_capacity = queued() ? static_cast<int>(queue_.capacity()) : 0;
  c.max_queue_depth = max_depth_.load(std::memory_order_relaxed);
  const std::int64_t pushed = c.submitted;
  c.mean_queue_depth = pushed > 0
                           ? static_cast<double>(depth_sum_.load(std::memory_order_relaxed)) /
                                 static_cast<double>(pushed)
                           : 0.0;
  return c;
}

void FrameWorker::run() {
  pinCurrentThreadToCpu(cpu_, "tracking");
  pipeline::FrameTicket ticket;
  while (concurrency::popWaiting(queue_, ticket, stop_)) {
    const ImageU8& image = pool_->image(ticket.buffer);
    try {
      handler_(FrameView{image.view(), ticket.timestamp, ticket.exposure_ms}, ticket.enqueued_ns);
    } catch (const std::exception& e) {
      spdlog::error("frame at t = {} s failed: {}", ticket.timestamp, e.what());
    }
    pool_->release(ticket.buffer);
    processed_.store(processed_.load(std::memory_order_relaxed) + 1, std::memory_order_release);
  }
}

}  // namespace ldsm
