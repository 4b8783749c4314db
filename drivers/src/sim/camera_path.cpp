// Uniform B-spline evaluation (de Boor) and camera orientation along the path.
#include "ldsm/drivers/sim/camera_path.h"

#include <cmath>
#include <limits>
#include <string>

#include "ldsm/drivers/sim/det_math.h"
#include "ldsm/error.h"

namespace ldsm::drivers::sim {
namespace {

constexpr int kDegree = 5;

int wrapIndex(long long i, int n) {
  long long r = i % n;
  if (r < 0) r += n;
  return static_cast<int>(r);
}

// de Boor on unit knots for span i (points i..i+degree) at local parameter u in [0, 1].
Vec3 deBoor(const std::vector<Vec3>& pts, int degree, bool closed, long long span, double u) {
  const int n = static_cast<int>(pts.size());
  Vec3 d[kDegree + 1];
  for (int j = 0; j <= degree; ++j) {
    const long long idx = span + j;
    d[j] = closed ? pts[static_cast<std::size_t>(wrapIndex(idx, n))]
                  : pts[static_cast<std::size_t>(idx)];
  }
  for (int r = 1; r <= degree; ++r) {
    for (int j = degree; j >= r; --j) {
      const double alpha =
          (u + static_cast<double>(degree - j)) / static_cast<double>(degree + 1 - r);
      d[j] = (1.0 - alpha) * d[j - 1] + alpha * d[j];
    }
  }
  return d[degree];
}

void splitParameter(const std::vector<Vec3>& pts, int degree, bool closed, double s,
                    long long& span, double& u) {
  const int n = static_cast<int>(pts.size());
  if (degree < 1 || degree > kDegree || n < degree + 1)
    throw InputError("sim path: a degree-" + std::to_string(degree) + " B-spline needs at least " +
                     std::to_string(degree + 1) + " control points, got " + std::to_string(n));
  if (!std::isfinite(s)) throw InputError("sim path: spline parameter is not finite");
  double fs = std::floor(s);
  if (closed) {
    // Reduce to [0, n) so the local parameter keeps its precision on long runs.
    const double nn = static_cast<double>(n);
    const double k = std::floor(s / nn);
    s -= k * nn;
    if (s >= nn) s -= nn;
    if (s < 0.0) s = 0.0;
    fs = std::floor(s);
  } else {
    const double last = static_cast<double>(n - degree);  // s in [0, last]
    if (s < 0.0 || s > last)
      throw InputError("sim path: parameter " + std::to_string(s) +
                       " outside the open spline [0, " + std::to_string(last) + "]");
    if (fs >= last) fs = last - 1.0;
  }
  span = static_cast<long long>(fs);
  u = s - fs;
}

double sumOfSines(const std::vector<SineTerm>& terms, double t) {
  double sum = 0.0;
  for (const SineTerm& term : terms) {
    double cycles = t / term.period_s;
    cycles -= std::floor(cycles);
    sum += term.amplitude * detSin(2.0 * kPi * cycles + term.phase);
  }
  return sum;
}

}  // namespace

Vec3 evaluateUniformBSpline(const std::vector<Vec3>& points, int degree, bool closed, double s) {
  long long span = 0;
  double u = 0.0;
  splitParameter(points, degree, closed, s, span, u);
  return deBoor(points, degree, closed, span, u);
}

Vec3 evaluateUniformBSplineDerivative(const std::vector<Vec3>& points, int degree, bool closed,
                                      double s) {
  long long span = 0;
  double u = 0.0;
  splitParameter(points, degree, closed, s, span, u);
  // The derivative of a uniform (unit-knot) B-spline of degree p is the degree p-1 spline over the
  // differences of consecutive control points, on the same knots shifted by one.
  const int n = static_cast<int>(points.size());
  std::vector<Vec3> diff(static_cast<std::size_t>(closed ? n : n - 1));
  for (std::size_t i = 0; i < diff.size(); ++i)
    diff[i] = points[(i + 1) % static_cast<std::size_t>(n)] - points[i];
  return deBoor(diff, degree - 1, closed, span, u);
}

double CameraPath::duration() const {
  if (closed) return std::numeric_limits<double>::infinity();
  const double spans = static_cast<double>(control_points.size()) - kDegree - start_span;
  return spans > 0.0 ? spans * span_duration_s : 0.0;
}

double CameraPath::period() const {
  return closed ? static_cast<double>(control_points.size()) * span_duration_s : 0.0;
}

RigidPose evaluatePath(const CameraPath& path, double t) {
  if (!(path.span_duration_s > 0.0)) throw InputError("sim path: span duration must be positive");
  if (!std::isfinite(t) || t < 0.0 || t > path.duration() * (1.0 + 1e-12))
    throw InputError("sim path: time " + std::to_string(t) + " s outside the path [0, " +
                     std::to_string(path.duration()) + "] s");
  const double s = path.start_span + t / path.span_duration_s;
  const Vec3 spline_pos = evaluateUniformBSpline(path.control_points, kDegree, path.closed, s);

  Vec3 forward = path.fixed_heading;
  if (path.heading_from_tangent)
    forward = evaluateUniformBSplineDerivative(path.control_points, kDegree, path.closed, s);
  forward.z = 0.0;
  if (!(norm(forward) > 1e-9))
    throw InputError("sim path: the heading is undefined (no horizontal motion) at t = " +
                     std::to_string(t));
  forward = normalized(forward);
  const Vec3 up{0, 0, 1};
  const Vec3 right = cross(forward, up);
  const Vec3 down = -up;
  const Mat3 heading = Mat3::fromColumns(right, down, forward);

  double sy, cy, sp, cp, sr, cr;
  detSinCos(sumOfSines(path.yaw, t), sy, cy);
  detSinCos(sumOfSines(path.pitch, t), sp, cp);
  detSinCos(sumOfSines(path.roll, t), sr, cr);
  // In camera axes: yaw about -y (up), pitch about -x (looking up), roll about z.
  const Mat3 yaw = axisRotation({0, -1, 0}, sy, cy);
  const Mat3 pitch = axisRotation({-1, 0, 0}, sp, cp);
  const Mat3 roll = axisRotation({0, 0, 1}, sr, cr);

  RigidPose pose;
  pose.rotation = heading * ((yaw * pitch) * roll);
  const double lateral = sumOfSines(path.lateral, t);
  const double vertical = sumOfSines(path.vertical, t);
  pose.translation = (spline_pos + lateral * right) + vertical * up;
  return pose;
}

}  // namespace ldsm::drivers::sim
