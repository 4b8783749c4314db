#include "client_channel.h"

#include <utility>

#include "thread_priority.h"

namespace ldsm::viewer {

ClientChannel::ClientChannel(Writer write) : write_(std::move(write)) {
  thread_ = std::thread([this] { run(); });
}

ClientChannel::~ClientChannel() {
  stop();
}

bool ClientChannel::offer(std::vector<WireMessage> batch) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (busy_ || stop_ || failed_) return false;
    pending_ = std::move(batch);
    busy_ = true;
  }
  cv_.notify_one();
  return true;
}

void ClientChannel::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  cv_.notify_one();
  if (thread_.joinable()) thread_.join();
}

bool ClientChannel::failed() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return failed_;
}

std::size_t ClientChannel::sentBytes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return sent_bytes_;
}

void ClientChannel::run() {
  lowerThisThreadPriority();
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    cv_.wait(lock, [this] { return stop_ || busy_; });
    if (stop_) return;
    std::vector<WireMessage> batch = std::move(pending_);
    lock.unlock();
    bool ok = true;
    std::size_t bytes = 0;
    for (const WireMessage& m : batch) {
      ok = write_(m);
      if (!ok) break;
      bytes += m.bytes.size();
    }
    lock.lock();
    sent_bytes_ += bytes;
    busy_ = false;
    if (!ok) {
      failed_ = true;
      return;
    }
  }
}

}  // namespace ldsm::viewer
