// The `ldsm` Python module (docs/python.md): the engine, dataset readers, calibration loaders and
// trajectory evaluation of the C++ libraries, with ldsm's errors as Python exceptions.
#include <pybind11/pybind11.h>
#include <spdlog/spdlog.h>

#include "ldsm/error.h"
#include "py_config.h"
#include "py_modules.h"

namespace py = pybind11;

PYBIND11_MODULE(ldsm, m) {
  m.doc() = "ldsm: live monocular direct SLAM (C++ engine, numpy in and out)";
  // Quiet by default, as the ldsm tool.
  spdlog::set_level(spdlog::level::err);
  static py::exception<ldsm::Error> error(m, "Error", PyExc_RuntimeError);
  static py::exception<ldsm::InputError> input_error(m, "InputError", error.ptr());
  static py::exception<ldsm::ConfigError> config_error(m, "ConfigError", error.ptr());
  static py::exception<ldsm::DeviceError> device_error(m, "DeviceError", error.ptr());
  // The most specific first.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const ldsm::InputError& e) {
      input_error(e.what());
    } catch (const ldsm::ConfigError& e) {
      config_error(e.what());
    } catch (const ldsm::DeviceError& e) {
      device_error(e.what());
    } catch (const ldsm::Error& e) {
      error(e.what());
    }
  });
  m.def(
      "set_log_level",
      [](const std::string& level) {
        const auto l = spdlog::level::from_str(level);
        if (l == spdlog::level::off && level != "off")
          throw ldsm::ConfigError("set_log_level: unknown level \"" + level +
                                  "\" (trace, debug, info, warn, error, off)");
        spdlog::set_level(l);
      },
      py::arg("level"), "trace, debug, info, warn, error (default) or off");
  ldsm::python::bindConfig(m);
  ldsm::python::bindCalibration(m);
  ldsm::python::bindDataset(m);
  ldsm::python::bindSystem(m);
  ldsm::python::bindEvaluation(m);
  m.attr("__version__") = LDSM_PYTHON_VERSION;
}
