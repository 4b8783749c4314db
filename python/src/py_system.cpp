// ldsm.System for Python: the engine with numpy frames in and numpy arrays out. The GIL is
// released while the engine works (submit, finish); events reach the Python callback on the
// caller's thread (event_queue.h).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <limits>
#include <memory>
#include <optional>

#include "arrays.h"
#include "event_queue.h"
#include "ldsm/error.h"
#include "ldsm/system.h"
#include "py_config.h"
#include "py_modules.h"

namespace ldsm::python {
namespace {

class PySystem {
 public:
  PySystem(const py::object& config, const GeometricCalibration& geometric,
           const std::optional<PhotometricCalibration>& photometric)
      : system_(std::make_unique<System>(toConfig(config), geometric,
                                         photometric ? *photometric : PhotometricCalibration{})) {
    system_->setListener(&events_);
  }

  void submit(const py::handle& frame, double timestamp, const py::object& exposure_ms) {
    if (!system_) throw Error("System: finish() was called; make a new System");
    py::object keep;
    FrameView view;
    view.image = arrayToImage(frame, keep);
    view.timestamp = timestamp;
    view.exposure_ms = exposure_ms.is_none() ? std::numeric_limits<double>::quiet_NaN()
                                             : exposure_ms.cast<double>();
    {
      py::gil_scoped_release release;
      system_->submit(view);
    }
    deliver();
  }

  void finish() {
    if (system_) {
      py::gil_scoped_release release;
      system_->finish();
    }
    deliver();
  }

  void deliver() {
    std::deque<AnyEvent> pending = events_.take();
    if (callback_.is_none()) return;
    for (const AnyEvent& e : pending) callback_(eventToDict(e));
  }

  const System& system() const {
    if (!system_) throw Error("System is closed");
    return *system_;
  }
  System& system() {
    if (!system_) throw Error("System is closed");
    return *system_;
  }

  py::object callback_ = py::none();
  EventQueue events_;

 private:
  std::unique_ptr<System> system_;
};

py::dict timingToDict(const StageTiming& t) {
  return py::dict(py::arg("count") = t.count, py::arg("mean_ms") = t.mean_ms,
                  py::arg("p50_ms") = t.p50_ms, py::arg("p99_ms") = t.p99_ms,
                  py::arg("max_ms") = t.max_ms);
}

py::dict pinholeToDict(const PinholeIntrinsics& p) {
  return py::dict(py::arg("fx") = p.fx, py::arg("fy") = p.fy, py::arg("cx") = p.cx,
                  py::arg("cy") = p.cy, py::arg("width") = p.width, py::arg("height") = p.height);
}

/// The estimate fields CalibrationStats and CalibrationSample share.
template <typename T>
void putEstimate(py::dict& d, const T& c) {
  d["radial_applied"] = c.radial_applied;
  d["radial_estimate"] = c.radial_estimate;
  d["focal_scale_estimate"] = c.focal_scale_estimate;
  d["cx_shift_estimate"] = c.cx_shift_estimate;
  d["cy_shift_estimate"] = c.cy_shift_estimate;
  d["radial_sigma"] = c.radial_sigma;
  d["focal_scale_sigma"] = c.focal_scale_sigma;
  d["cx_sigma"] = c.cx_sigma;
  d["cy_sigma"] = c.cy_sigma;
  d["realistic_radial_sigma"] = c.realistic_radial_sigma;
  d["realistic_focal_scale_sigma"] = c.realistic_focal_scale_sigma;
  d["realistic_cx_sigma"] = c.realistic_cx_sigma;
  d["realistic_cy_sigma"] = c.realistic_cy_sigma;
  d["windows"] = c.windows;
}

/// The online calibration refinement: where it stands and how it got there (one entry per
/// fused window, bounded as SystemStats::calibration_history is).
py::dict calibrationToDict(const SystemStats& s) {
  py::dict d;
  d["configured"] = pinholeToDict(s.calibration.configured);
  d["applied"] = pinholeToDict(s.calibration.applied);
  putEstimate(d, s.calibration);
  py::list history;
  for (const CalibrationSample& h : s.calibration_history) {
    py::dict e;
    putEstimate(e, h);
    e["frame_index"] = h.frame_index;
    e["timestamp"] = h.timestamp;
    e["applied"] = pinholeToDict(h.applied);
    history.append(e);
  }
  d["history"] = history;
  return d;
}

py::dict statsToDict(const SystemStats& s) {
  py::dict d;
  d["frames"] = s.frames;
  d["tracked_frames"] = s.tracked_frames;
  d["keyframes"] = s.keyframes;
  d["initializations"] = s.initializations;
  d["tracking_losses"] = s.tracking_losses;
  d["initializer_frames"] = s.initializer_frames;
  d["initializer_busy_frames"] = s.initializer_busy_frames;
  d["rejected_frames"] = s.rejected_frames;
  d["submitted_frames"] = s.submitted_frames;
  d["dropped_frames"] = s.dropped_frames;
  d["loops"] = s.loops_closed;
  d["retired_frames"] = s.retired_frames;
  d["map_points"] = s.map.points;
  d["map_bytes"] = s.map.bytes;
  d["reactivations"] = s.reuse.reactivations;
  d["calibration"] = calibrationToDict(s);
  py::dict stages, latency;
  for (const StageTiming& t : s.stages) stages[t.stage.c_str()] = timingToDict(t);
  for (const StageTiming& t : s.latency) latency[t.stage.c_str()] = timingToDict(t);
  d["stages"] = stages;
  d["latency"] = latency;
  return d;
}

}  // namespace

void bindSystem(py::module_& m) {
  py::class_<PySystem>(m, "System",
                       "Monocular direct SLAM: submit 8-bit grey frames, read the trajectory and "
                       "the map back as numpy arrays.")
      .def(py::init<const py::object&, const GeometricCalibration&,
                    const std::optional<PhotometricCalibration>&>(),
           py::arg("config"), py::arg("calibration"), py::arg("photometric") = py::none(),
           "config: None, an ldsm.Config, a dict of sections or a YAML path; calibration: from "
           "ldsm.load_calibration() or a dataset's .calibration")
      .def("submit", &PySystem::submit, py::arg("frame"), py::arg("timestamp"),
           py::arg("exposure_ms") = py::none(),
           "Processes (deterministic) or queues one (H, W) uint8 frame; timestamp in seconds, "
           "increasing. Raises ldsm.InputError for a frame of the wrong type or size.")
      .def("finish", &PySystem::finish,
           "Waits until every submitted frame is processed and the last optimisation is done.")
      .def(
          "trajectory",
          [](const PySystem& s) { return trajectoryToArray(s.system().trajectory()); },
          "(N, 8) float64 array: t tx ty tz qx qy qz qw per tracked frame (camera-to-world)")
      .def(
          "take_retired_frames",
          [](PySystem& s) { return trajectoryToArray(s.system().takeRetiredFrames()); },
          "(R, 8) float64 array: the frames that left memory since the last call "
          "(system.frame_history; live mode), oldest first; trajectory() continues them")
      .def(
          "keyframe_trajectory",
          [](const PySystem& s) { return trajectoryToArray(s.system().keyframeTrajectory()); },
          "(K, 8) float64 array of the keyframes' poses")
      .def(
          "map_points", [](const PySystem& s) { return mapPointsToArray(s.system().mapPoints()); },
          "(P, 4) float64 array: x y z intensity per map point (world coordinates)")
      .def(
          "latest_pose",
          [](PySystem& s) -> py::object {
            const std::optional<StampedPose> p = s.system().latestPose();
            if (!p) return py::none();
            return trajectoryToArray({*p})[py::int_(0)];
          },
          "The newest tracked pose as (8,) t tx ty tz qx qy qz qw, or None")
      .def(
          "status", [](const PySystem& s) { return std::string(toString(s.system().status())); },
          "\"initializing\", \"tracking\" or \"lost\"")
      .def(
          "stats", [](const PySystem& s) { return statsToDict(s.system().stats()); },
          "Counts and timings as a dict")
      .def(
          "rectified_camera",
          [](const PySystem& s) {
            const PinholeIntrinsics k = s.system().rectifiedCamera();
            return py::dict(py::arg("fx") = k.fx, py::arg("fy") = k.fy, py::arg("cx") = k.cx,
                            py::arg("cy") = k.cy, py::arg("width") = k.width,
                            py::arg("height") = k.height);
          },
          "The ideal pinhole the engine works in")
      .def(
          "on_event",
          [](PySystem& s, const py::object& callback) {
            if (!callback.is_none() && !PyCallable_Check(callback.ptr()))
              throw InputError("on_event: the callback must be callable or None");
            s.callback_ = callback;
            s.events_.enable(!callback.is_none());
          },
          py::arg("callback"),
          "callback(event: dict) for every event, called on this thread at the end of submit(), "
          "finish() and poll_events() (None: no callback)")
      .def("poll_events", &PySystem::deliver, "Hands waiting events to the callback now")
      .def_property_readonly(
          "dropped_events", [](const PySystem& s) { return s.events_.dropped(); },
          "Events dropped because more than 100000 were waiting");
}

}  // namespace ldsm::python
