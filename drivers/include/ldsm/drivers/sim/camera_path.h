// Smooth camera trajectories of the synthetic scenes: a uniform quintic B-spline (C4) through
// control points for the position, the heading along the path (or a fixed heading), and sums of
// sines for small head motion (yaw, pitch, roll, sideways and vertical sway). Evaluated with the
// deterministic functions of det_math.h, so poses are bit-identical on every platform.
#pragma once

#include <vector>

#include "ldsm/drivers/sim/det_vec.h"

namespace ldsm::drivers::sim {

/// amplitude * sin(2 pi t / period_s + phase)
struct SineTerm {
  double amplitude = 0.0;
  double period_s = 1.0;
  double phase = 0.0;
};

struct CameraPath {
  /// Positions (world, metres; z up) of a uniform quintic B-spline.
  std::vector<Vec3> control_points;
  /// Closed: the control polygon repeats and the path is periodic with period
  /// control_points.size() * span_duration_s. Open: the path runs over the spans whose six control
  /// points exist, starting at span start_span.
  bool closed = true;
  double span_duration_s = 1.0;  ///< seconds per B-spline span
  double start_span = 0.0;       ///< spline parameter at t = 0 (open paths)
  /// Look along the horizontal direction of motion, or along fixed_heading.
  bool heading_from_tangent = true;
  Vec3 fixed_heading{1, 0, 0};
  std::vector<SineTerm> yaw;       ///< radians, positive turns left (about world up)
  std::vector<SineTerm> pitch;     ///< radians, positive looks up
  std::vector<SineTerm> roll;      ///< radians, about the optical axis
  std::vector<SineTerm> lateral;   ///< metres along the camera's right axis (horizontal)
  std::vector<SineTerm> vertical;  ///< metres along world up

  /// Seconds the path lasts: +inf for closed paths.
  double duration() const;
  /// Seconds for one traversal of a closed path (0 for open paths).
  double period() const;
};

/// Camera-to-world pose at time t (seconds). Camera axes: x right, y down, z forward; the world is
/// z up. Throws ldsm::InputError if t lies outside [0, duration()] or the path is malformed.
RigidPose evaluatePath(const CameraPath& path, double t);

/// Position of the uniform B-spline of degree `degree` over `points` at parameter s (span index
/// plus fraction; the span i uses points i..i+degree, wrapped when `closed`).
Vec3 evaluateUniformBSpline(const std::vector<Vec3>& points, int degree, bool closed, double s);

/// Derivative with respect to s of the same spline.
Vec3 evaluateUniformBSplineDerivative(const std::vector<Vec3>& points, int degree, bool closed,
                                      double s);

}  // namespace ldsm::drivers::sim
