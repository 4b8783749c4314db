// SO(3): 3D rotations stored as a unit quaternion, templated on the scalar (double, float,
// ceres::Jet). Tangent vectors are rotation vectors w (axis * angle), hat(w) v = w x v, and the
// group acts on points by rotation. Jacobian conventions (used throughout ldsm):
//   left Jacobian  Jl(w):  exp(w + dw) ~ exp(Jl(w) dw) * exp(w)
//   right Jacobian Jr(w):  exp(w + dw) ~ exp(w) * exp(Jr(w) dw),   Jr(w) = Jl(-w) = Jl(w)^T
// so d log(exp(d) * R) / dd = Jl^-1(log R) and d log(R * exp(d)) / dd = Jr^-1(log R) at d = 0.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

#include "math/lie_coefficients.h"

namespace ldsm {

template <typename S>
class SO3 {
 public:
  using Scalar = S;
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  using Matrix3 = Eigen::Matrix<S, 3, 3>;
  using Quaternion = Eigen::Quaternion<S>;
  using Tangent = Vector3;
  using Adjoint = Matrix3;
  static constexpr int kDoF = 3;

  /// Identity rotation.
  SO3() : q_(Quaternion::Identity()) {}
  /// From any non-zero quaternion (normalised here).
  explicit SO3(const Quaternion& q) : q_(q.normalized()) {}
  /// From a rotation matrix (orthonormal, det +1; not checked). The nearest unit quaternion of a
  /// slightly non-orthogonal matrix is used.
  explicit SO3(const Matrix3& R) : q_(Quaternion(R).normalized()) {}

  static SO3 identity() { return SO3(); }

  /// exp(w): rotation by |w| about w / |w|.
  static SO3 exp(const Tangent& w) {
    const S theta2 = w.squaredNorm();
    const S f = lie::sinHalfOverTheta(theta2);
    return SO3(Quaternion(lie::cosHalf(theta2), f * w.x(), f * w.y(), f * w.z()), Unchecked{});
  }

  /// log(R): the rotation vector with angle in [0, pi]. Accurate near 0 and near pi (at exactly
  /// pi either of the two opposite vectors is returned).
  Tangent log() const {
    // q and -q are the same rotation; w >= 0 gives the angle in [0, pi].
    const bool flip = q_.w() < S(0);
    const S w = flip ? S(-q_.w()) : q_.w();
    const Vector3 v = flip ? Vector3(-q_.vec()) : Vector3(q_.vec());
    return lie::quaternionLogFactor(v.squaredNorm(), w) * v;
  }

  /// Rotation angle in [0, pi].
  S angle() const {
    using std::abs;
    using std::atan2;
    return S(2) * atan2(q_.vec().norm(), abs(q_.w()));
  }

  /// hat(w) = [w]x, the skew-symmetric matrix with hat(w) v = w x v.
  static Matrix3 hat(const Tangent& w) {
    Matrix3 W;
    W << S(0), -w.z(), w.y(), w.z(), S(0), -w.x(), -w.y(), w.x(), S(0);
    return W;
  }
  /// vee(W) = (W(2,1), W(0,2), W(1,0)), so vee(hat(w)) = w.
  static Tangent vee(const Matrix3& W) { return Tangent(W(2, 1), W(0, 2), W(1, 0)); }

  SO3 operator*(const SO3& o) const {
    Quaternion q = q_ * o.q_;
    q.normalize();  // keep rounding drift from accumulating over long chains
    return SO3(q, Unchecked{});
  }
  SO3& operator*=(const SO3& o) { return *this = *this * o; }
  /// Rotates a point.
  Vector3 operator*(const Vector3& p) const { return q_ * p; }

  SO3 inverse() const { return SO3(q_.conjugate(), Unchecked{}); }
  Matrix3 matrix() const { return q_.toRotationMatrix(); }
  /// Ad(R) = R: exp(R w) = R exp(w) R^-1.
  Adjoint adjoint() const { return matrix(); }
  const Quaternion& quaternion() const { return q_; }
  /// Renormalises the stored quaternion.
  void normalize() { q_.normalize(); }

  template <typename T>
  SO3<T> cast() const {
    return SO3<T>(q_.template cast<T>());
  }

  /// Left Jacobian Jl(w) = I + (1 - cos t)/t^2 hat(w) + (t - sin t)/t^3 hat(w)^2, t = |w|.
  static Matrix3 leftJacobian(const Tangent& w) {
    const S theta2 = w.squaredNorm();
    const Matrix3 W = hat(w);
    return Matrix3::Identity() + lie::oneMinusCosOverTheta2(theta2) * W +
           lie::thetaMinusSinOverTheta3(theta2) * (W * W);
  }
  /// Right Jacobian Jr(w) = Jl(-w).
  static Matrix3 rightJacobian(const Tangent& w) { return leftJacobian(Tangent(-w)); }
  /// Jl(w)^-1 = I - hat(w)/2 + (1/t^2 - cot(t/2)/(2t)) hat(w)^2; finite for |w| <= pi.
  static Matrix3 leftJacobianInverse(const Tangent& w) {
    const Matrix3 W = hat(w);
    return Matrix3::Identity() - S(0.5) * W +
           lie::inverseJacobianCoefficient(S(w.squaredNorm())) * (W * W);
  }
  /// Jr(w)^-1 = Jl(-w)^-1.
  static Matrix3 rightJacobianInverse(const Tangent& w) { return leftJacobianInverse(Tangent(-w)); }

  /// d (exp(d) * q) / dd at d = 0 for a point q (already rotated): -hat(q). For (exp(d) * R) * p
  /// pass q = R * p.
  static Matrix3 actionJacobianAtIdentity(const Vector3& q) { return -hat(q); }
  /// d ((exp(d) * R) * p) / dd at d = 0.
  Matrix3 actionJacobianLeft(const Vector3& p) const { return -hat(*this * p); }
  /// d ((R * exp(d)) * p) / dd at d = 0 = -R hat(p).
  Matrix3 actionJacobianRight(const Vector3& p) const { return -matrix() * hat(p); }
  /// d (R * p) / dp = R.
  Matrix3 actionJacobianPoint() const { return matrix(); }

 private:
  struct Unchecked {};
  SO3(const Quaternion& q, Unchecked) : q_(q) {}
  template <typename>
  friend class SO3;

  Quaternion q_;
};

using SO3d = SO3<double>;
using SO3f = SO3<float>;

/// Geodesic interpolation R0 * exp(alpha * log(R0^-1 R1)); alpha = 0 gives R0, 1 gives R1.
template <typename S>
SO3<S> interpolate(const SO3<S>& R0, const SO3<S>& R1, const typename SO3<S>::Scalar& alpha) {
  return R0 * SO3<S>::exp(alpha * (R0.inverse() * R1).log());
}

}  // namespace ldsm
