// Small 3-vectors and 3x3 matrices in double with a fixed evaluation order, for the deterministic
// synthetic renderer (Eigen may vectorise and reorder sums differently on SSE and NEON).
#pragma once

#include <cmath>

namespace ldsm::drivers::sim {

struct Vec3 {
  double x = 0, y = 0, z = 0;
};

inline Vec3 operator+(const Vec3& a, const Vec3& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
inline Vec3 operator-(const Vec3& a, const Vec3& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
inline Vec3 operator-(const Vec3& a) {
  return {-a.x, -a.y, -a.z};
}
inline Vec3 operator*(double s, const Vec3& a) {
  return {s * a.x, s * a.y, s * a.z};
}
inline double dot(const Vec3& a, const Vec3& b) {
  return (a.x * b.x + a.y * b.y) + a.z * b.z;
}
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double norm(const Vec3& a) {
  return std::sqrt(dot(a, a));
}
inline Vec3 normalized(const Vec3& a) {
  const double n = norm(a);
  return {a.x / n, a.y / n, a.z / n};
}

/// Row-major 3x3 matrix.
struct Mat3 {
  double m[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};

  static Mat3 fromColumns(const Vec3& c0, const Vec3& c1, const Vec3& c2) {
    Mat3 r;
    r.m[0][0] = c0.x, r.m[1][0] = c0.y, r.m[2][0] = c0.z;
    r.m[0][1] = c1.x, r.m[1][1] = c1.y, r.m[2][1] = c1.z;
    r.m[0][2] = c2.x, r.m[1][2] = c2.y, r.m[2][2] = c2.z;
    return r;
  }
  Vec3 col(int j) const { return {m[0][j], m[1][j], m[2][j]}; }
  Vec3 row(int i) const { return {m[i][0], m[i][1], m[i][2]}; }
  Mat3 transposed() const {
    Mat3 r;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) r.m[i][j] = m[j][i];
    return r;
  }
};

inline Vec3 operator*(const Mat3& a, const Vec3& v) {
  return {dot(a.row(0), v), dot(a.row(1), v), dot(a.row(2), v)};
}

inline Mat3 operator*(const Mat3& a, const Mat3& b) {
  Mat3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      r.m[i][j] = (a.m[i][0] * b.m[0][j] + a.m[i][1] * b.m[1][j]) + a.m[i][2] * b.m[2][j];
  return r;
}

/// Rotation by angle (given as its sine and cosine) about the unit axis.
inline Mat3 axisRotation(const Vec3& axis, double s, double c) {
  const double t = 1.0 - c;
  const double x = axis.x, y = axis.y, z = axis.z;
  Mat3 r;
  r.m[0][0] = t * x * x + c, r.m[0][1] = t * x * y - s * z, r.m[0][2] = t * x * z + s * y;
  r.m[1][0] = t * x * y + s * z, r.m[1][1] = t * y * y + c, r.m[1][2] = t * y * z - s * x;
  r.m[2][0] = t * x * z - s * y, r.m[2][1] = t * y * z + s * x, r.m[2][2] = t * z * z + c;
  return r;
}

/// Unit quaternion (w, x, y, z) of a rotation matrix, w >= 0.
struct Quat {
  double w = 1, x = 0, y = 0, z = 0;
};

inline Quat quatFromMatrix(const Mat3& r) {
  const auto& m = r.m;
  const double tr = (m[0][0] + m[1][1]) + m[2][2];
  Quat q;
  if (tr > 0.0) {
    const double s = 2.0 * std::sqrt(tr + 1.0);
    q.w = 0.25 * s;
    q.x = (m[2][1] - m[1][2]) / s;
    q.y = (m[0][2] - m[2][0]) / s;
    q.z = (m[1][0] - m[0][1]) / s;
  } else if (m[0][0] > m[1][1] && m[0][0] > m[2][2]) {
    const double s = 2.0 * std::sqrt(((1.0 + m[0][0]) - m[1][1]) - m[2][2]);
    q.w = (m[2][1] - m[1][2]) / s;
    q.x = 0.25 * s;
    q.y = (m[0][1] + m[1][0]) / s;
    q.z = (m[0][2] + m[2][0]) / s;
  } else if (m[1][1] > m[2][2]) {
    const double s = 2.0 * std::sqrt(((1.0 + m[1][1]) - m[0][0]) - m[2][2]);
    q.w = (m[0][2] - m[2][0]) / s;
    q.x = (m[0][1] + m[1][0]) / s;
    q.y = 0.25 * s;
    q.z = (m[1][2] + m[2][1]) / s;
  } else {
    const double s = 2.0 * std::sqrt(((1.0 + m[2][2]) - m[0][0]) - m[1][1]);
    q.w = (m[1][0] - m[0][1]) / s;
    q.x = (m[0][2] + m[2][0]) / s;
    q.y = (m[1][2] + m[2][1]) / s;
    q.z = 0.25 * s;
  }
  if (q.w < 0.0) q = {-q.w, -q.x, -q.y, -q.z};
  const double n = std::sqrt(((q.w * q.w + q.x * q.x) + q.y * q.y) + q.z * q.z);
  return {q.w / n, q.x / n, q.y / n, q.z / n};
}

/// Rotation matrix of a unit quaternion.
inline Mat3 matrixFromQuat(const Quat& q) {
  const double w = q.w, x = q.x, y = q.y, z = q.z;
  Mat3 r;
  r.m[0][0] = 1.0 - 2.0 * (y * y + z * z);
  r.m[0][1] = 2.0 * (x * y - w * z);
  r.m[0][2] = 2.0 * (x * z + w * y);
  r.m[1][0] = 2.0 * (x * y + w * z);
  r.m[1][1] = 1.0 - 2.0 * (x * x + z * z);
  r.m[1][2] = 2.0 * (y * z - w * x);
  r.m[2][0] = 2.0 * (x * z - w * y);
  r.m[2][1] = 2.0 * (y * z + w * x);
  r.m[2][2] = 1.0 - 2.0 * (x * x + y * y);
  return r;
}

/// A rigid camera-to-world transform: p_world = rotation * p_camera + translation.
struct RigidPose {
  Mat3 rotation;
  Vec3 translation;
};

}  // namespace ldsm::drivers::sim
