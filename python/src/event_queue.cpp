#include "event_queue.h"

#include <pybind11/stl.h>

namespace ldsm::python {
namespace {

py::list poseList(const Pose& p) {
  py::list l;
  for (double v : {p.translation.x(), p.translation.y(), p.translation.z(), p.rotation.x(),
                   p.rotation.y(), p.rotation.z(), p.rotation.w()})
    l.append(v);
  return l;
}

struct ToDict {
  py::dict operator()(const FrameEvent& e) const {
    py::dict d;
    d["type"] = "frame";
    d["frame_index"] = e.frame_index;
    d["timestamp"] = e.timestamp;
    d["status"] = toString(e.status);
    d["has_pose"] = e.has_pose;
    d["pose"] = e.has_pose ? py::object(poseList(e.pose)) : py::object(py::none());
    d["is_keyframe"] = e.is_keyframe;
    d["residual_rmse"] = e.residual_rmse;
    return d;
  }
  py::dict operator()(const KeyframeEvent& e) const {
    py::dict d;
    d["type"] = "keyframe";
    d["keyframe_id"] = e.keyframe_id;
    d["frame_index"] = e.frame_index;
    d["timestamp"] = e.timestamp;
    d["pose"] = poseList(e.pose);
    d["active_points"] = e.active_points;
    return d;
  }
  py::dict operator()(const InitializedEvent& e) const {
    py::dict d;
    d["type"] = "initialized";
    d["frame_index"] = e.frame_index;
    d["timestamp"] = e.timestamp;
    d["points"] = e.points;
    return d;
  }
  py::dict operator()(const TrackingLostEvent& e) const {
    py::dict d;
    d["type"] = "tracking_lost";
    d["frame_index"] = e.frame_index;
    d["timestamp"] = e.timestamp;
    d["reason"] = e.reason;
    return d;
  }
  py::dict operator()(const LoopClosureEvent& e) const {
    py::dict d;
    d["type"] = "loop_closure";
    d["current_keyframe_id"] = e.current_keyframe_id;
    d["matched_keyframe_id"] = e.matched_keyframe_id;
    d["inliers"] = e.inliers;
    d["scale"] = e.scale;
    d["time_ms"] = e.time_ms;
    d["drift_chi2"] = e.drift_chi2;
    d["corrected_keyframes"] = e.corrected_keyframes;
    return d;
  }
  py::dict operator()(const ReuseEvent& e) const {
    py::dict d;
    d["type"] = "reuse";
    d["keyframe_id"] = e.keyframe_id;
    d["frame_index"] = e.frame_index;
    d["timestamp"] = e.timestamp;
    d["reactivated"] = e.reactivated;
    return d;
  }
  py::dict operator()(const RelocalizedEvent& e) const {
    py::dict d;
    d["type"] = "relocalized";
    d["frame_index"] = e.frame_index;
    d["timestamp"] = e.timestamp;
    d["keyframe_id"] = e.keyframe_id;
    d["map_keyframe_id"] = e.map_keyframe_id;
    d["lost_seconds"] = e.lost_seconds;
    return d;
  }
};

}  // namespace

void EventQueue::push(AnyEvent e) {
  if (!enabled_.load(std::memory_order_relaxed)) return;
  std::lock_guard<std::mutex> lock(mutex_);
  if (events_.size() >= capacity_) {
    events_.pop_front();
    ++dropped_;
  }
  events_.push_back(std::move(e));
}

std::deque<AnyEvent> EventQueue::take() {
  std::lock_guard<std::mutex> lock(mutex_);
  std::deque<AnyEvent> out;
  out.swap(events_);
  return out;
}

std::size_t EventQueue::dropped() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return dropped_;
}

py::dict eventToDict(const AnyEvent& event) {
  return std::visit(ToDict{}, event);
}

}  // namespace ldsm::python
