#include "arrays.h"

#include <cmath>

#include "ldsm/error.h"

namespace ldsm::python {

py::array_t<double> trajectoryToArray(const Trajectory& trajectory) {
  py::array_t<double> out({static_cast<py::ssize_t>(trajectory.size()), py::ssize_t{8}});
  auto a = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < trajectory.size(); ++i) {
    const StampedPose& p = trajectory[i];
    const auto r = static_cast<py::ssize_t>(i);
    a(r, 0) = p.timestamp;
    a(r, 1) = p.pose.translation.x();
    a(r, 2) = p.pose.translation.y();
    a(r, 3) = p.pose.translation.z();
    a(r, 4) = p.pose.rotation.x();
    a(r, 5) = p.pose.rotation.y();
    a(r, 6) = p.pose.rotation.z();
    a(r, 7) = p.pose.rotation.w();
  }
  return out;
}

Trajectory arrayToTrajectory(const py::handle& array, const std::string& what) {
  py::array_t<double, py::array::c_style | py::array::forcecast> a;
  try {
    a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(array);
  } catch (const py::error_already_set&) {
    a = {};
  }
  if (!a || a.ndim() != 2 || a.shape(1) != 8)
    throw InputError(what + ": expected an (N, 8) array of t tx ty tz qx qy qz qw");
  const auto v = a.unchecked<2>();
  Trajectory t;
  t.reserve(static_cast<std::size_t>(a.shape(0)));
  for (py::ssize_t i = 0; i < a.shape(0); ++i) {
    for (py::ssize_t k = 0; k < 8; ++k)
      if (!std::isfinite(v(i, k)))
        throw InputError(what + ": row " + std::to_string(i) + " has a non-finite value");
    StampedPose p;
    p.timestamp = v(i, 0);
    p.pose.translation = {v(i, 1), v(i, 2), v(i, 3)};
    p.pose.rotation = Eigen::Quaterniond(v(i, 7), v(i, 4), v(i, 5), v(i, 6));
    if (p.pose.rotation.norm() < 1e-9)
      throw InputError(what + ": row " + std::to_string(i) + " has a zero quaternion");
    p.pose.rotation.normalize();
    t.push_back(p);
  }
  return t;
}

py::array_t<double> mapPointsToArray(const std::vector<MapPoint>& points) {
  py::array_t<double> out({static_cast<py::ssize_t>(points.size()), py::ssize_t{4}});
  auto a = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto r = static_cast<py::ssize_t>(i);
    a(r, 0) = points[i].position.x();
    a(r, 1) = points[i].position.y();
    a(r, 2) = points[i].position.z();
    a(r, 3) = points[i].intensity;
  }
  return out;
}

py::array_t<std::uint8_t> imageToArray(ImageView<const std::uint8_t> image) {
  py::array_t<std::uint8_t> out(
      {static_cast<py::ssize_t>(image.height), static_cast<py::ssize_t>(image.width)});
  auto a = out.mutable_unchecked<2>();
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) a(y, x) = image(x, y);
  return out;
}

ImageView<const std::uint8_t> arrayToImage(const py::handle& frame, py::object& keep) {
  if (!py::isinstance<py::array>(frame))
    throw InputError("frame must be a numpy uint8 array of shape (H, W), got " +
                     std::string(py::str(py::type::of(frame).attr("__name__"))));
  auto arr = py::reinterpret_borrow<py::array>(frame);
  std::string shape;
  for (py::ssize_t i = 0; i < arr.ndim(); ++i)
    shape += (i ? ", " : "") + std::to_string(arr.shape(i));
  if (arr.dtype().kind() != 'u' || arr.itemsize() != 1 || arr.ndim() != 2)
    throw InputError("frame must be a numpy uint8 array of shape (H, W), got " +
                     std::string(py::str(arr.dtype())) + " of shape (" + shape + ")");
  if (arr.shape(0) == 0 || arr.shape(1) == 0) throw InputError("frame is empty (" + shape + ")");
  if (arr.strides(1) != 1 || arr.strides(0) < arr.shape(1))
    arr = py::array_t<std::uint8_t, py::array::c_style>::ensure(arr);  // contiguous copy
  keep = arr;
  ImageView<const std::uint8_t> view;
  view.data = static_cast<const std::uint8_t*>(arr.data());
  view.width = static_cast<int>(arr.shape(1));
  view.height = static_cast<int>(arr.shape(0));
  view.stride = static_cast<int>(arr.strides(0));
  return view;
}

}  // namespace ldsm::python
