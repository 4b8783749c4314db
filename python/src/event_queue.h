// Events for a Python callback. The engine's threads never call into Python (they would wait for
// the GIL): the listener queues copies of the events, and the module hands them to the callback
// on the caller's thread at the end of submit(), finish() and poll_events().
#pragma once

#include <pybind11/pybind11.h>

#include <atomic>
#include <cstddef>
#include <deque>
#include <mutex>
#include <variant>

#include "ldsm/events.h"

namespace ldsm::python {

namespace py = pybind11;

using AnyEvent = std::variant<FrameEvent, KeyframeEvent, InitializedEvent, TrackingLostEvent,
                              LoopClosureEvent, ReuseEvent, RelocalizedEvent>;

class EventQueue : public SystemListener {
 public:
  /// At most `capacity` events wait; older ones are dropped (and counted) beyond that.
  explicit EventQueue(std::size_t capacity = 100000) : capacity_(capacity) {}

  void onFrame(const FrameEvent& e) override { push(e); }
  void onKeyframe(const KeyframeEvent& e) override { push(e); }
  void onInitialized(const InitializedEvent& e) override { push(e); }
  void onTrackingLost(const TrackingLostEvent& e) override { push(e); }
  void onLoopClosure(const LoopClosureEvent& e) override { push(e); }
  void onReuse(const ReuseEvent& e) override { push(e); }
  void onRelocalized(const RelocalizedEvent& e) override { push(e); }

  /// Events are only queued while enabled (a callback is set).
  void enable(bool on) { enabled_.store(on); }

  /// Takes every waiting event (caller's thread).
  std::deque<AnyEvent> take();
  std::size_t dropped() const;

 private:
  void push(AnyEvent e);

  std::atomic<bool> enabled_{false};
  std::size_t capacity_;
  mutable std::mutex mutex_;
  std::deque<AnyEvent> events_;
  std::size_t dropped_ = 0;
};

/// An event as a dict: {"type": "frame" | "keyframe" | "initialized" | "tracking_lost" |
/// "loop_closure" | "reuse" | "relocalized", ...its fields}.
py::dict eventToDict(const AnyEvent& event);

}  // namespace ldsm::python
