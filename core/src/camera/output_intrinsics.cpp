// computeOutputIntrinsics(): the output pinhole for DSO's crop / full / none / explicit modes.
#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include "camera_common.h"
#include "ldsm/camera/rectifier.h"
#include "ldsm/error.h"

namespace ldsm {
namespace {

/// Number of steps across the full window by which crop shrinks a window edge.
constexpr int kCropSteps = 1000;
/// Crop never starts wider than this in normalized coordinates (about 84 degrees off-axis).
constexpr double kMaxTan = 10.0;

std::string fmt(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

std::string sizeText(int w, int h) {
  return std::to_string(w) + "x" + std::to_string(h);
}

/// A window [x0, x1] x [y0, y1] of the undistorted (normalized) image plane.
struct Window {
  double x0, x1, y0, y1;
};

/// The pinhole that puts pixel centers 0 and size - 1 on the window borders.
PinholeIntrinsics fromWindow(const Window& w, int width, int height) {
  PinholeIntrinsics out;
  out.width = width;
  out.height = height;
  out.fx = (width > 1 ? width - 1 : 1) / (w.x1 - w.x0);
  out.fy = (height > 1 ? height - 1 : 1) / (w.y1 - w.y0);
  out.cx = width > 1 ? -w.x0 * out.fx : -0.5 * (w.x0 + w.x1) * out.fx;
  out.cy = height > 1 ? -w.y0 * out.fy : -0.5 * (w.y0 + w.y1) * out.fy;
  return out;
}

/// Normalized coordinates of the undistorted input border (every border pixel). `complete` is set
/// to false when some border pixel does not unproject to a ray in front of the camera.
std::vector<Eigen::Vector2d> undistortedBorder(const CameraModel& cam, bool* complete) {
  const int w = cam.width(), h = cam.height();
  std::vector<Eigen::Vector2d> pts;
  pts.reserve(2 * static_cast<std::size_t>(w + h));
  *complete = true;
  const auto add = [&](double u, double v) {
    Eigen::Vector3d ray;
    if (!cam.unproject({u, v}, &ray) || !(ray.z() > 1e-6)) {
      *complete = false;
      return;
    }
    pts.emplace_back(ray.x() / ray.z(), ray.y() / ray.z());
  };
  for (int u = 0; u < w; ++u) {
    add(u, 0);
    add(u, h - 1);
  }
  for (int v = 0; v < h; ++v) {
    add(0, v);
    add(w - 1, v);
  }
  return pts;
}

Window boundingWindow(const std::vector<Eigen::Vector2d>& pts) {
  Window win{pts[0].x(), pts[0].x(), pts[0].y(), pts[0].y()};
  for (const auto& p : pts) {
    win.x0 = std::min(win.x0, p.x());
    win.x1 = std::max(win.x1, p.x());
    win.y0 = std::min(win.y0, p.y());
    win.y1 = std::max(win.y1, p.y());
  }
  return win;
}

Window fullWindow(const CameraModel& cam) {
  bool complete = false;
  const auto border = undistortedBorder(cam, &complete);
  if (!complete || border.empty())
    throw InputError(
        "rectification: output mode full is impossible: part of the input image border is 90 "
        "degrees or more off the optical axis or outside the camera model's valid domain (use "
        "crop or an explicit output)");
  return boundingWindow(border);
}

/// True when `n` + 1 evenly spaced samples from (xa, ya) to (xb, yb) all hit the input image.
bool segmentValid(const CameraModel& cam, double xa, double ya, double xb, double yb, int n) {
  Eigen::Vector2d px;
  for (int i = 0; i <= n; ++i) {
    const double t = n > 0 ? static_cast<double>(i) / n : 0.0;
    if (!camera_detail::sampleInput(cam, xa + t * (xb - xa), ya + t * (yb - ya), &px)) return false;
  }
  return true;
}

bool allPixelsValid(const CameraModel& cam, const PinholeIntrinsics& out) {
  Eigen::Vector2d px;
  for (int v = 0; v < out.height; ++v)
    for (int u = 0; u < out.width; ++u)
      if (!camera_detail::sampleInput(cam, (u - out.cx) / out.fx, (v - out.cy) / out.fy, &px))
        return false;
  return true;
}

PinholeIntrinsics cropOutput(const CameraModel& cam, int width, int height) {
  bool complete = false;
  const auto border = undistortedBorder(cam, &complete);
  if (border.empty())
    throw InputError(
        "rectification: crop found no input border pixel the camera model can "
        "unproject");
  Window win = boundingWindow(border);
  win.x0 = std::max(win.x0, -kMaxTan);
  win.x1 = std::min(win.x1, kMaxTan);
  win.y0 = std::max(win.y0, -kMaxTan);
  win.y1 = std::min(win.y1, kMaxTan);
  const double dx = (win.x1 - win.x0) / kCropSteps, dy = (win.y1 - win.y0) / kCropSteps;
  const int nx = std::max(width - 1, 1), ny = std::max(height - 1, 1);
  const auto shrinkable = [&]() { return win.x1 - win.x0 > 2 * dx && win.y1 - win.y0 > 2 * dy; };
  // Greedy: move every window edge that still touches invalid input inwards by one step. The
  // edges are sampled at the output pixel centers they will hold.
  while (true) {
    if (!shrinkable()) throw InputError("rectification: crop found no valid input region");
    const bool top = segmentValid(cam, win.x0, win.y0, win.x1, win.y0, nx);
    const bool bottom = segmentValid(cam, win.x0, win.y1, win.x1, win.y1, nx);
    const bool left = segmentValid(cam, win.x0, win.y0, win.x0, win.y1, ny);
    const bool right = segmentValid(cam, win.x1, win.y0, win.x1, win.y1, ny);
    if (top && bottom && left && right) break;
    if (!top) win.y0 += dy;
    if (!bottom) win.y1 -= dy;
    if (!left) win.x0 += dx;
    if (!right) win.x1 -= dx;
  }
  // The border is valid; make sure no interior pixel is not (non-convex valid regions).
  PinholeIntrinsics out = fromWindow(win, width, height);
  while (!allPixelsValid(cam, out)) {
    win = {win.x0 + dx, win.x1 - dx, win.y0 + dy, win.y1 - dy};
    if (!shrinkable()) throw InputError("rectification: crop found no valid input region");
    out = fromWindow(win, width, height);
  }
  return out;
}

bool hasDistortion(const CameraIntrinsics& in) {
  return std::any_of(in.distortion.begin(), in.distortion.end(), [](double d) { return d != 0.0; });
}

PinholeIntrinsics explicitOutput(const RectificationSpec& spec) {
  const auto check = [&](double v, const char* name, bool must_be_positive) {
    if (!std::isfinite(v))
      throw InputError(std::string("rectification: explicit output ") + name + " is not finite (" +
                       fmt(v) + ")");
    if (must_be_positive && v <= 0)
      throw InputError(std::string("rectification: explicit output ") + name +
                       " must be positive (got " + fmt(v) + ")");
  };
  check(spec.fx, "fx", true);
  check(spec.fy, "fy", true);
  check(spec.cx, "cx", false);
  check(spec.cy, "cy", false);
  PinholeIntrinsics out;
  out.width = spec.width;
  out.height = spec.height;
  if (spec.relative) {
    out.fx = spec.fx * spec.width;
    out.fy = spec.fy * spec.height;
    out.cx = spec.cx * spec.width - 0.5;
    out.cy = spec.cy * spec.height - 0.5;
  } else {
    out.fx = spec.fx;
    out.fy = spec.fy;
    out.cx = spec.cx;
    out.cy = spec.cy;
  }
  return out;
}

}  // namespace

PinholeIntrinsics computeOutputIntrinsics(const CameraModel& input, const RectificationSpec& spec) {
  if (spec.width <= 0 || spec.height <= 0)
    throw InputError("rectification: output size must be positive (got " +
                     sizeText(spec.width, spec.height) + ")");
  const CameraIntrinsics& in = input.intrinsics();
  switch (spec.mode) {
    case OutputMode::None: {
      if (hasDistortion(in))
        throw InputError(std::string("rectification: output mode none needs an undistorted "
                                     "pinhole input, but the input is ") +
                         cameraModelName(in.model) + " with distortion (use crop or full)");
      const double sx = static_cast<double>(spec.width) / in.width;
      const double sy = static_cast<double>(spec.height) / in.height;
      return {in.fx * sx, in.fy * sy, (in.cx + 0.5) * sx - 0.5, (in.cy + 0.5) * sy - 0.5,
              spec.width, spec.height};
    }
    case OutputMode::Crop:
    case OutputMode::Full: {
      const char* name = spec.mode == OutputMode::Crop ? "crop" : "full";
      if (spec.width > in.width || spec.height > in.height)
        throw InputError(std::string("rectification: ") + name + " output size " +
                         sizeText(spec.width, spec.height) + " is larger than the input " +
                         sizeText(in.width, in.height));
      if (spec.mode == OutputMode::Crop) return cropOutput(input, spec.width, spec.height);
      return fromWindow(fullWindow(input), spec.width, spec.height);
    }
    case OutputMode::Explicit:
      return explicitOutput(spec);
  }
  throw InputError("rectification: unknown output mode " +
                   std::to_string(static_cast<int>(spec.mode)));
}

}  // namespace ldsm
