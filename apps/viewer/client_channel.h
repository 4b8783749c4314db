// One connected page: what the publisher hands it and what it holds. The page's own connection
// thread (a civetweb worker, at the lowest priority) runs serve(), which writes each batch the
// publisher offers to the page's HTTP stream, so a slow page (or network) only ever delays
// itself. The channel holds at most one batch: while a batch is still being written, offer()
// refuses the next one and the publisher sends that page a catch-up delta later (the page misses
// intermediate states, never data).
#pragma once

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <vector>

#include "stream_delta.h"
#include "wire_format.h"

namespace ldsm::viewer {

class ClientChannel {
 public:
  /// `write(message)` sends one message and returns false when the connection failed.
  using Writer = std::function<bool(const WireMessage&)>;
  ClientChannel() = default;
  ClientChannel(const ClientChannel&) = delete;
  ClientChannel& operator=(const ClientChannel&) = delete;

  /// Hands a batch to serve(); false (batch not taken) while the previous one is still being
  /// sent, after the connection failed or after stop().
  bool offer(std::vector<WireMessage> batch);
  /// Writes the batches offered, in order, on the calling thread until stop() is called (true)
  /// or a write fails (false).
  bool serve(const Writer& write);
  /// No more batches are taken; serve() returns once the one offered before is written. Does not
  /// wait for that.
  void stop();
  bool failed() const;
  std::size_t sentBytes() const;

  // The publisher's bookkeeping of what this page holds (publisher thread only).
  PageStream trajectory, keyframes, points;
  std::int64_t image_frame = -2;  ///< frame index of the image the page has

 private:
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::vector<WireMessage> pending_;
  bool busy_ = false;
  bool stop_ = false;
  bool failed_ = false;
  std::size_t sent_bytes_ = 0;
};

}  // namespace ldsm::viewer
