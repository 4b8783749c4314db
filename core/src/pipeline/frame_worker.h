// Runs frame processing on a background thread for the System's threaded mode: submit() copies
// the frame into one of a fixed number of preallocated slots and returns; the worker processes
// slots in order. In offline use the producer waits when all slots are full (nothing is dropped).
#pragma once

#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "ldsm/system.h"

namespace ldsm {

class FrameWorker {
 public:
  using Handler = std::function<void(const FrameView&)>;

  explicit FrameWorker(Handler handler, int slots = 4);
  ~FrameWorker();

  /// Copies the frame into a free slot (waits for one) and queues it.
  void push(const FrameView& frame);
  /// Waits until every queued frame has been processed.
  void drain();
  /// Processes what is queued, then ends the thread.
  void stop();

 private:
  struct Slot {
    ImageU8 image;
    double timestamp = 0.0;
    double exposure_ms = 0.0;
  };
  void run();

  Handler handler_;
  std::vector<Slot> slots_;
  std::deque<int> free_;
  std::deque<int> queued_;
  bool busy_ = false;
  bool stopping_ = false;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::thread thread_;
};

}  // namespace ldsm
