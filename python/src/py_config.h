// ldsm.Config for Python, and what ldsm.System accepts as its configuration.
#pragma once

#include <pybind11/pybind11.h>

#include "ldsm/config.h"

namespace ldsm::python {

namespace py = pybind11;

void bindConfig(py::module_& m);

/// A Config from None (the defaults), an ldsm.Config, a dict of sections ({"system":
/// {"deterministic": True}}) or a path to a YAML file. Throws ldsm::ConfigError naming the key
/// that is wrong.
Config toConfig(const py::handle& value);

}  // namespace ldsm::python
