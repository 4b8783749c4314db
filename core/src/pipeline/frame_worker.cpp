#include "pipeline/frame_worker.h"

#include <spdlog/spdlog.h>

#include <exception>

namespace ldsm {

FrameWorker::FrameWorker(Handler handler, int slots)
    : handler_(std::move(handler)), slots_(static_cast<size_t>(slots)) {
  for (int i = 0; i < slots; ++i) free_.push_back(i);
  thread_ = std::thread([this] { run(); });
}

FrameWorker::~FrameWorker() {
  stop();
}

void FrameWorker::push(const FrameView& frame) {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [&] { return !free_.empty() || stopping_; });
  if (stopping_) return;
  const int s = free_.front();
  free_.pop_front();
  lock.unlock();
  Slot& slot = slots_[static_cast<size_t>(s)];
  slot.image.copyFrom(frame.image);
  slot.timestamp = frame.timestamp;
  slot.exposure_ms = frame.exposure_ms;
  lock.lock();
  queued_.push_back(s);
  changed_.notify_all();
}

void FrameWorker::drain() {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [&] { return queued_.empty() && !busy_; });
}

void FrameWorker::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!thread_.joinable()) return;
    stopping_ = true;
    changed_.notify_all();
  }
  thread_.join();
}

void FrameWorker::run() {
  for (;;) {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [&] { return !queued_.empty() || stopping_; });
    if (queued_.empty()) return;  // stopping and nothing left
    const int s = queued_.front();
    queued_.pop_front();
    busy_ = true;
    lock.unlock();
    const Slot& slot = slots_[static_cast<size_t>(s)];
    try {
      handler_(FrameView{slot.image.view(), slot.timestamp, slot.exposure_ms});
    } catch (const std::exception& e) {
      spdlog::error("frame at t = {} s failed: {}", slot.timestamp, e.what());
    }
    lock.lock();
    busy_ = false;
    free_.push_back(s);
    changed_.notify_all();
  }
}

}  // namespace ldsm
