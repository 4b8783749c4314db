// Uniform quintic B-spline paths: exactness on lines, derivatives against numeric
// differentiation, smoothness across knots, periodicity and range errors.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "ldsm/drivers/sim/camera_path.h"
#include "ldsm/drivers/sim/det_math.h"
#include "ldsm/error.h"

namespace ldsm::drivers::sim {
namespace {

std::vector<Vec3> wavyPoints(int n) {
  std::vector<Vec3> pts;
  for (int i = 0; i < n; ++i)
    pts.push_back({std::cos(0.7 * i) * 3.0 + i, std::sin(1.3 * i), 0.1 * i * i});
  return pts;
}

TEST(CameraPath, SplineReproducesStraightLines) {
  std::vector<Vec3> line;
  for (int i = 0; i < 12; ++i) line.push_back({2.0 * i - 1.0, 0.5 * i, 3.0});
  for (double s = 0.0; s <= 7.0; s += 0.173) {
    const Vec3 p = evaluateUniformBSpline(line, 5, false, s);
    // Uniform B-splines reproduce linear functions: span s starts at the Greville point of
    // control point s + (degree - 1) / 2.
    EXPECT_NEAR(p.x, 2.0 * (s + 2.0) - 1.0, 1e-12);
    EXPECT_NEAR(p.y, 0.5 * (s + 2.0), 1e-12);
    EXPECT_NEAR(p.z, 3.0, 1e-12);
    const Vec3 d = evaluateUniformBSplineDerivative(line, 5, false, s);
    EXPECT_NEAR(d.x, 2.0, 1e-12);
    EXPECT_NEAR(d.y, 0.5, 1e-12);
  }
}

TEST(CameraPath, DerivativeMatchesNumericDifferentiation) {
  const auto pts = wavyPoints(15);
  for (bool closed : {false, true}) {
    for (double s = 0.3; s < 9.0; s += 0.41) {
      const double h = 1e-5;
      const Vec3 a = evaluateUniformBSpline(pts, 5, closed, s + h);
      const Vec3 b = evaluateUniformBSpline(pts, 5, closed, s - h);
      const Vec3 d = evaluateUniformBSplineDerivative(pts, 5, closed, s);
      EXPECT_NEAR(d.x, (a.x - b.x) / (2 * h), 1e-6);
      EXPECT_NEAR(d.y, (a.y - b.y) / (2 * h), 1e-6);
      EXPECT_NEAR(d.z, (a.z - b.z) / (2 * h), 1e-6);
    }
  }
}

TEST(CameraPath, SecondAndThirdDerivativesAreContinuousAcrossKnots) {
  const auto pts = wavyPoints(14);
  const double h = 1e-3;
  auto second = [&](double s) {
    const Vec3 a = evaluateUniformBSplineDerivative(pts, 5, false, s + h);
    const Vec3 b = evaluateUniformBSplineDerivative(pts, 5, false, s - h);
    return Vec3{(a.x - b.x) / (2 * h), (a.y - b.y) / (2 * h), (a.z - b.z) / (2 * h)};
  };
  for (int knot = 2; knot <= 7; ++knot) {
    // One-sided estimates just before and after the knot agree (C2; the quintic is even C4).
    const Vec3 before = second(knot - 3 * h), after = second(knot + 3 * h);
    EXPECT_NEAR(before.x, after.x, 0.05) << "knot " << knot;
    EXPECT_NEAR(before.y, after.y, 0.05) << "knot " << knot;
    EXPECT_NEAR(before.z, after.z, 0.05) << "knot " << knot;
  }
}

TEST(CameraPath, ClosedPathIsPeriodic) {
  CameraPath p;
  for (int i = 0; i < 10; ++i)
    p.control_points.push_back(
        {3.0 * std::cos(0.6283185307179586 * i), 2.0 * std::sin(0.6283185307179586 * i), 1.0});
  p.closed = true;
  p.span_duration_s = 0.7;
  p.yaw = {{0.1, p.period() / 3, 0.2}};
  p.pitch = {{0.05, p.period() / 5, 0.0}};
  p.lateral = {{0.2, p.period() / 2, 1.0}};
  EXPECT_DOUBLE_EQ(p.period(), 7.0);
  EXPECT_TRUE(std::isinf(p.duration()));
  for (double t : {0.0, 1.3, 4.4}) {
    const RigidPose a = evaluatePath(p, t), b = evaluatePath(p, t + p.period());
    EXPECT_NEAR(norm(a.translation - b.translation), 0.0, 1e-12);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(a.rotation.m[r][c], b.rotation.m[r][c], 1e-12);
  }
}

TEST(CameraPath, CameraLooksAlongTheMotionAndStaysLevel) {
  CameraPath p;
  for (int i = 0; i < 12; ++i) p.control_points.push_back({0.0, 1.0 * i, 1.5});  // along +y
  p.closed = false;
  p.span_duration_s = 1.0;
  const RigidPose pose = evaluatePath(p, 2.0);
  // Camera z (third column) looks along +y, camera y (down) points to -z.
  EXPECT_NEAR(pose.rotation.m[1][2], 1.0, 1e-12);
  EXPECT_NEAR(pose.rotation.m[2][1], -1.0, 1e-12);
  EXPECT_NEAR(pose.translation.y, 2.0 + 2.0, 1e-12);
  // Rotation matrices stay orthonormal with head motion added.
  p.yaw = {{0.3, 2.0, 0.0}};
  p.roll = {{0.2, 3.0, 0.5}};
  const Mat3 r = evaluatePath(p, 1.1).rotation;
  const Mat3 rtr = r.transposed() * r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(rtr.m[i][j], i == j ? 1.0 : 0.0, 1e-14);
}

TEST(CameraPath, RejectsTimesOutsideTheOpenPathAndMalformedPaths) {
  CameraPath p;
  for (int i = 0; i < 8; ++i) p.control_points.push_back({1.0 * i, 0, 0});
  p.closed = false;
  p.span_duration_s = 0.5;
  EXPECT_DOUBLE_EQ(p.duration(), 1.5);
  EXPECT_NO_THROW(evaluatePath(p, 1.5));
  EXPECT_THROW(evaluatePath(p, 1.6), InputError);
  EXPECT_THROW(evaluatePath(p, -0.1), InputError);
  EXPECT_THROW(evaluatePath(p, std::numeric_limits<double>::quiet_NaN()), InputError);
  p.control_points.resize(4);
  EXPECT_THROW(evaluatePath(p, 0.0), InputError);
  CameraPath still;  // no horizontal motion and heading from the tangent
  for (int i = 0; i < 8; ++i) still.control_points.push_back({0, 0, 0.1 * i});
  still.closed = false;
  EXPECT_THROW(evaluatePath(still, 0.5), InputError);
}

}  // namespace
}  // namespace ldsm::drivers::sim
