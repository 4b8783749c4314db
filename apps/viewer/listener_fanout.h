// One SystemListener that passes every event on to two others (the System takes one listener):
// `ldsm run --serve` gives the progress counter and the viewer the same events.
#pragma once

#include "ldsm/events.h"

namespace ldsm::viewer {

class ListenerFanout : public SystemListener {
 public:
  ListenerFanout(SystemListener* first, SystemListener* second) : a_(first), b_(second) {}
  void onFrame(const FrameEvent& e) override {
    if (a_) a_->onFrame(e);
    if (b_) b_->onFrame(e);
  }
  void onKeyframe(const KeyframeEvent& e) override {
    if (a_) a_->onKeyframe(e);
    if (b_) b_->onKeyframe(e);
  }
  void onInitialized(const InitializedEvent& e) override {
    if (a_) a_->onInitialized(e);
    if (b_) b_->onInitialized(e);
  }
  void onTrackingLost(const TrackingLostEvent& e) override {
    if (a_) a_->onTrackingLost(e);
    if (b_) b_->onTrackingLost(e);
  }
  void onLoopClosure(const LoopClosureEvent& e) override {
    if (a_) a_->onLoopClosure(e);
    if (b_) b_->onLoopClosure(e);
  }
  void onReuse(const ReuseEvent& e) override {
    if (a_) a_->onReuse(e);
    if (b_) b_->onReuse(e);
  }
  void onRelocalized(const RelocalizedEvent& e) override {
    if (a_) a_->onRelocalized(e);
    if (b_) b_->onRelocalized(e);
  }

 private:
  SystemListener* a_;
  SystemListener* b_;
};

}  // namespace ldsm::viewer
