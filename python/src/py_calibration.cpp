// Calibration loaders for Python: geometric (camera.txt, Kalibr/EuRoC YAML, KITTI calib.txt) and
// photometric (pcalib.txt, vignette image).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "ldsm/calib/calibration_loader.h"
#include "ldsm/calib/photometric_files.h"
#include "ldsm/camera/calibration.h"
#include "py_modules.h"

namespace ldsm::python {

void bindCalibration(py::module_& m) {
  py::class_<GeometricCalibration>(m, "Calibration", "A camera's geometric calibration")
      .def_property_readonly("width", [](const GeometricCalibration& c) { return c.input.width; })
      .def_property_readonly("height", [](const GeometricCalibration& c) { return c.input.height; })
      .def_property_readonly("fx", [](const GeometricCalibration& c) { return c.input.fx; })
      .def_property_readonly("fy", [](const GeometricCalibration& c) { return c.input.fy; })
      .def_property_readonly("cx", [](const GeometricCalibration& c) { return c.input.cx; })
      .def_property_readonly("cy", [](const GeometricCalibration& c) { return c.input.cy; })
      .def_property_readonly("distortion",
                             [](const GeometricCalibration& c) { return c.input.distortion; })
      .def("__repr__", [](const GeometricCalibration& c) {
        return "ldsm.Calibration(" + std::to_string(c.input.width) + "x" +
               std::to_string(c.input.height) + ", fx=" + std::to_string(c.input.fx) + ")";
      });
  py::class_<PhotometricCalibration>(m, "PhotometricCalibration",
                                     "Inverse response and vignette (either may be absent)")
      .def(py::init<>())
      .def_property_readonly("has_response",
                             [](const PhotometricCalibration& p) { return p.has_response; })
      .def_property_readonly("has_vignette",
                             [](const PhotometricCalibration& p) { return !p.vignette.empty(); });
  m.def(
      "load_calibration",
      [](const std::string& path, int width, int height) {
        return calib::loadGeometricCalibration(path, width, height);
      },
      py::arg("path"), py::arg("width") = 0, py::arg("height") = 0,
      "Reads a DSO camera.txt, a EuRoC/Kalibr YAML or a KITTI calib.txt (give width and height "
      "for KITTI)");
  m.def(
      "load_photometric",
      [](const std::string& pcalib, const std::string& vignette, int width, int height) {
        return calib::loadPhotometricCalibration(pcalib, vignette, width, height);
      },
      py::arg("pcalib") = "", py::arg("vignette") = "", py::arg("width") = 0, py::arg("height") = 0,
      "Reads pcalib.txt and/or a vignette image (empty path: not known)");
}

}  // namespace ldsm::python
