// The parts of the ldsm Python module, one file each.
#pragma once

#include <pybind11/pybind11.h>

namespace ldsm::python {

namespace py = pybind11;

void bindSystem(py::module_& m);
void bindDataset(py::module_& m);
void bindCalibration(py::module_& m);
void bindEvaluation(py::module_& m);

}  // namespace ldsm::python
