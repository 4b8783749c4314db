// The one route by which events leave the engine: every stage reports to the EventSink, which
// forwards to the application's listener and keeps the loop events for the statistics. In
// deterministic mode every call comes on the caller's thread; in threaded mode frame, loss and
// relocalised events come from the tracking thread, initialisation, keyframe and reuse
// (reactivated) events from the mapping thread, and loop events from the mapping thread or, at
// the end of a run, from the thread calling System::finish() (events.h).
#pragma once

#include <cstdint>
#include <deque>
#include <mutex>
#include <vector>

#include "ldsm/events.h"
#include "ldsm/system.h"  // SystemStats::kMaxLoopEvents

namespace ldsm {

class EventSink {
 public:
  /// Set before the first frame; null: no listener.
  void setListener(SystemListener* listener) { listener_ = listener; }

  void frame(const FrameEvent& e) {
    if (listener_) listener_->onFrame(e);
  }
  void keyframe(const KeyframeEvent& e) {
    if (listener_) listener_->onKeyframe(e);
  }
  void initialized(const InitializedEvent& e) {
    if (listener_) listener_->onInitialized(e);
  }
  void trackingLost(const TrackingLostEvent& e) {
    if (listener_) listener_->onTrackingLost(e);
  }
  void relocalized(const RelocalizedEvent& e) {
    if (listener_) listener_->onRelocalized(e);
  }
  void reactivated(const ReuseEvent& e) {
    if (listener_) listener_->onReuse(e);
  }
  void loopClosed(const LoopClosureEvent& e) {
    {
      std::lock_guard<std::mutex> lock(loops_mutex_);
      loops_.push_back(e);
      // A long run closes a loop every few seconds: only the newest are kept, and the count.
      if (loops_.size() > kMaxLoopEvents) loops_.pop_front();
      ++loops_closed_;
    }
    if (listener_) listener_->onLoopClosure(e);
  }

  void mapsMerged(const MapMergeEvent& e) {
    if (listener_) listener_->onMapsMerged(e);
  }

  /// The newest kMaxLoopEvents loop events, in order (a copy; never waits for the stages).
  std::vector<LoopClosureEvent> loops() const {
    std::lock_guard<std::mutex> lock(loops_mutex_);
    return {loops_.begin(), loops_.end()};
  }
  /// Loop events so far, also those no longer kept.
  std::int64_t loopsClosed() const {
    std::lock_guard<std::mutex> lock(loops_mutex_);
    return loops_closed_;
  }
  static constexpr std::size_t kMaxLoopEvents = SystemStats::kMaxLoopEvents;

 private:
  SystemListener* listener_ = nullptr;
  mutable std::mutex loops_mutex_;
  std::deque<LoopClosureEvent> loops_;
  std::int64_t loops_closed_ = 0;
};

}  // namespace ldsm
