// Dataset readers for Python: `for frame in ldsm.open_dataset(path)` yields frames (numpy image,
// timestamp, exposure) of any layout `ldsm run` reads, with the dataset's calibration and ground
// truth.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "arrays.h"
#include "ldsm/drivers/dataset_calibration.h"
#include "ldsm/drivers/dataset_description.h"
#include "ldsm/drivers/dataset_source.h"
#include "ldsm/drivers/trajectory_io.h"
#include "py_modules.h"

namespace ldsm::python {
namespace {

struct PyFrame {
  std::int64_t index = 0;
  double timestamp = 0.0;
  py::object exposure_ms = py::none();
  py::array_t<std::uint8_t> image;
};

class PyDataset {
 public:
  PyDataset(const std::string& path, const std::string& format)
      : description_(drivers::describeDataset(path, drivers::parseDatasetFormat(format))),
        calibration_(drivers::loadDatasetCalibration(description_)) {}

  const drivers::DatasetDescription& description() const { return description_; }
  const drivers::DatasetCalibration& calibration() const { return calibration_; }

 private:
  drivers::DatasetDescription description_;
  drivers::DatasetCalibration calibration_;
};

class FrameIterator {
 public:
  explicit FrameIterator(const drivers::DatasetDescription& d) : source_(drivers::openDataset(d)) {}
  PyFrame next() {
    bool more = false;
    {
      py::gil_scoped_release release;
      more = source_->next(frame_);
    }
    if (!more) throw py::stop_iteration();
    PyFrame f;
    f.index = frame_.index;
    f.timestamp = frame_.timestamp;
    if (std::isfinite(frame_.exposure_ms)) f.exposure_ms = py::float_(frame_.exposure_ms);
    f.image = imageToArray(frame_.image.view());
    return f;
  }

 private:
  std::unique_ptr<drivers::FrameSource> source_;
  drivers::Frame frame_;
};

}  // namespace

void bindDataset(py::module_& m) {
  py::class_<PyFrame>(m, "Frame", "One frame of a dataset")
      .def_readonly("index", &PyFrame::index)
      .def_readonly("timestamp", &PyFrame::timestamp, "seconds")
      .def_readonly("exposure_ms", &PyFrame::exposure_ms, "milliseconds, None when unknown")
      .def_readonly("image", &PyFrame::image, "(H, W) uint8");
  py::class_<FrameIterator>(m, "FrameIterator")
      .def(
          "__iter__", [](FrameIterator& it) -> FrameIterator& { return it; },
          py::return_value_policy::reference_internal)
      .def("__next__", &FrameIterator::next);
  py::class_<PyDataset>(m, "Dataset", "A recorded sequence (TUM-Mono, EuRoC, KITTI, ...)")
      .def("__iter__", [](const PyDataset& d) { return FrameIterator(d.description()); })
      .def(
          "__len__",
          [](const PyDataset& d) {
            return static_cast<std::size_t>(std::max<std::int64_t>(d.description().frame_count, 0));
          })
      .def_property_readonly("path", [](const PyDataset& d) { return d.description().root; })
      .def_property_readonly("format",
                             [](const PyDataset& d) { return toString(d.description().format); })
      .def_property_readonly("width", [](const PyDataset& d) { return d.description().width; })
      .def_property_readonly("height", [](const PyDataset& d) { return d.description().height; })
      .def_property_readonly(
          "calibration", [](const PyDataset& d) { return d.calibration().geometric; },
          "The dataset's geometric calibration (ldsm.Calibration)")
      .def_property_readonly(
          "photometric", [](const PyDataset& d) { return d.calibration().photometric; },
          "The dataset's photometric calibration (may be empty)")
      .def(
          "groundtruth",
          [](const PyDataset& d) -> py::object {
            const drivers::DatasetDescription& desc = d.description();
            if (desc.groundtruth_file.empty()) return py::none();
            return trajectoryToArray(drivers::readTrajectory(
                desc.groundtruth_file, desc.groundtruth_format, &desc.timestamps));
          },
          "The ground truth as an (N, 8) array, or None");
  m.def(
      "open_dataset",
      [](const std::string& path, const std::string& format) { return PyDataset(path, format); },
      py::arg("path"), py::arg("format") = "auto",
      "Opens a sequence folder or video (format: auto, tum-mono, euroc, kitti, tum-rgbd, folder, "
      "video); iterate over it for its frames");
  m.def(
      "read_trajectory",
      [](const std::string& path) { return trajectoryToArray(drivers::readTrajectory(path)); },
      py::arg("path"), "Reads a TUM, EuRoC or KITTI trajectory file as an (N, 8) array");
  m.def(
      "write_trajectory",
      [](const std::string& path, const py::handle& array) {
        drivers::writeTumTrajectory(path, arrayToTrajectory(array, "write_trajectory"));
      },
      py::arg("path"), py::arg("trajectory"), "Writes an (N, 8) array as a TUM trajectory");
}

}  // namespace ldsm::python
