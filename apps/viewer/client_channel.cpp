#include "client_channel.h"

#include <utility>

namespace ldsm::viewer {

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
}

bool ClientChannel::failed() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return failed_;
}

std::size_t ClientChannel::sentBytes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return sent_bytes_;
}

bool ClientChannel::serve(const Writer& write) {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    cv_.wait(lock, [this] { return stop_ || busy_; });
    if (!busy_) return true;  // stopped; a batch offered before stop() is still written
    std::vector<WireMessage> batch = std::move(pending_);
    lock.unlock();
    bool ok = true;
    std::size_t bytes = 0;
    for (const WireMessage& m : batch) {
      ok = write(m);
      if (!ok) break;
      bytes += m.bytes.size();
    }
    lock.lock();
    sent_bytes_ += bytes;
    busy_ = false;
    if (!ok) {
      failed_ = true;
      return false;
    }
  }
}

}  // namespace ldsm::viewer
