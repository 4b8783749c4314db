// Conversions between ldsm's value types and numpy arrays for the Python module.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <string>
#include <vector>

#include "ldsm/image.h"
#include "ldsm/types.h"

namespace ldsm::python {

namespace py = pybind11;

/// (N, 8) float64: t, tx, ty, tz, qx, qy, qz, qw (TUM order, camera-to-world).
py::array_t<double> trajectoryToArray(const Trajectory& trajectory);

/// The inverse; throws ldsm::InputError naming `what` for a wrong shape or non-finite values.
Trajectory arrayToTrajectory(const py::handle& array, const std::string& what);

/// (N, 4) float64: x, y, z, intensity.
py::array_t<double> mapPointsToArray(const std::vector<MapPoint>& points);

/// A copy of an image as an (H, W) uint8 array.
py::array_t<std::uint8_t> imageToArray(ImageView<const std::uint8_t> image);

/// A view of an (H, W) uint8 array (rows may be strided, pixels contiguous). Throws
/// ldsm::InputError describing what was given when it is not that. `keep` receives the array
/// (possibly a contiguous copy) the view points into.
ImageView<const std::uint8_t> arrayToImage(const py::handle& frame, py::object& keep);

}  // namespace ldsm::python
