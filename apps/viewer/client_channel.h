// One connected page: a sender thread of its own writes the publisher's messages to the page's
// WebSocket, so a slow page (or network) only ever delays itself. The channel holds at most one
// batch: while a batch is still being written, offer() refuses the next one and the publisher
// sends that page a catch-up delta later (the page misses intermediate states, never data).
#pragma once

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "stream_delta.h"
#include "wire_format.h"

namespace ldsm::viewer {

class ClientChannel {
 public:
  /// `write(message)` sends one message and returns false when the connection failed.
  using Writer = std::function<bool(const WireMessage&)>;
  explicit ClientChannel(Writer write);
  ~ClientChannel();
  ClientChannel(const ClientChannel&) = delete;
  ClientChannel& operator=(const ClientChannel&) = delete;

  /// Hands a batch to the sender thread; false (batch not taken) while the previous one is
  /// still being sent or after the connection failed.
  bool offer(std::vector<WireMessage> batch);
  /// Stops the sender thread (the message being written is finished first).
  void stop();
  bool failed() const;
  std::size_t sentBytes() const;

  // The publisher's bookkeeping of what this page holds (publisher thread only).
  PageStream trajectory, keyframes, points;
  std::int64_t image_frame = -2;  ///< frame index of the image the page has

 private:
  void run();

  Writer write_;
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::vector<WireMessage> pending_;
  bool busy_ = false;
  bool stop_ = false;
  bool failed_ = false;
  std::size_t sent_bytes_ = 0;
  std::thread thread_;
};

}  // namespace ldsm::viewer
