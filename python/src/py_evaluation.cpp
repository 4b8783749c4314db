// Trajectory evaluation for Python: ATE after Sim(3)/SE(3) alignment and KITTI-style RPE, on
// (N, 8) arrays (t tx ty tz qx qy qz qw).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "arrays.h"
#include "ldsm/error.h"
#include "ldsm/eval/ate.h"
#include "ldsm/eval/rpe.h"
#include "py_modules.h"

namespace ldsm::python {

void bindEvaluation(py::module_& m) {
  m.def(
      "ate",
      [](const py::handle& gt, const py::handle& est, const std::string& align, double max_dt) {
        if (align != "sim3" && align != "se3")
          throw ConfigError("ate: align must be \"sim3\" or \"se3\", got \"" + align + "\"");
        const Trajectory g = arrayToTrajectory(gt, "ate: gt");
        const Trajectory e = arrayToTrajectory(est, "ate: est");
        eval::AteResult r;
        {
          py::gil_scoped_release release;
          r = eval::computeAte(g, e, align == "sim3" ? eval::AlignMode::Sim3 : eval::AlignMode::SE3,
                               max_dt);
        }
        return py::dict(
            py::arg("rmse") = r.rmse, py::arg("mean") = r.mean, py::arg("median") = r.median,
            py::arg("max") = r.max, py::arg("rotation_rmse_deg") = r.rotation_rmse_deg,
            py::arg("matched") = r.matched, py::arg("gt_path_length") = r.gt_path_length,
            py::arg("scale") = r.sim3_scale,
            py::arg("aligned_estimate") = trajectoryToArray(r.aligned_estimate));
      },
      py::arg("gt"), py::arg("est"), py::arg("align") = "sim3", py::arg("max_dt") = 0.02,
      "Absolute trajectory error after aligning est to gt (align: sim3 or se3)");
  m.def(
      "rpe",
      [](const py::handle& gt, const py::handle& est, std::vector<double> lengths, std::size_t step,
         double scale, double max_dt) {
        const Trajectory g = arrayToTrajectory(gt, "rpe: gt");
        const Trajectory e = arrayToTrajectory(est, "rpe: est");
        eval::RpeOptions o;
        o.lengths = std::move(lengths);
        o.step = step;
        o.scale = scale;
        o.max_dt = max_dt;
        eval::RpeResult r;
        {
          py::gil_scoped_release release;
          r = eval::computeRpe(g, e, o);
        }
        py::list per_length;
        for (const eval::RpeLengthStats& s : r.per_length)
          per_length.append(py::dict(py::arg("length") = s.length, py::arg("segments") = s.segments,
                                     py::arg("translation_percent") = s.translation_percent,
                                     py::arg("rotation_deg_per_m") = s.rotation_deg_per_m));
        return py::dict(py::arg("segments") = r.segments,
                        py::arg("translation_percent") = r.translation_percent,
                        py::arg("rotation_deg_per_m") = r.rotation_deg_per_m,
                        py::arg("per_length") = per_length);
      },
      py::arg("gt"), py::arg("est"), py::arg("lengths") = std::vector<double>{},
      py::arg("step") = 1, py::arg("scale") = 1.0, py::arg("max_dt") = 0.02,
      "KITTI-style relative pose error over path lengths (default: 10 %..80 % of the path)");
}

}  // namespace ldsm::python
