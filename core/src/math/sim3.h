// Sim(3): similarity transforms T = (R, t, s) acting as T * p = s R p + t (scale s > 0), templated
// on the scalar. Used for loop closure and pose-graph optimisation of monocular maps.
// Tangent order (everywhere in ldsm): x = [rho (translation, 3), phi (rotation, 3), sigma (log of
// the scale, 1)], hat(x) = [[hat(phi) + sigma I, rho], [0, 0]]. Jacobian conventions as in so3.h.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cassert>
#include <cmath>

#include "math/lie_coefficients.h"
#include "math/se3.h"
#include "math/so3.h"

namespace ldsm {

template <typename S>
class Sim3 {
 public:
  using Scalar = S;
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  using Matrix3 = Eigen::Matrix<S, 3, 3>;
  using Matrix4 = Eigen::Matrix<S, 4, 4>;
  using Quaternion = Eigen::Quaternion<S>;
  using Tangent = Eigen::Matrix<S, 7, 1>;  ///< [rho (translation), phi (rotation), sigma]
  using Adjoint = Eigen::Matrix<S, 7, 7>;
  using PointJacobian = Eigen::Matrix<S, 3, 7>;
  static constexpr int kDoF = 7;

  /// Identity transform.
  Sim3() : t_(Vector3::Zero()), s_(1) {}
  /// From a rotation, a translation and a scale > 0.
  Sim3(const SO3<S>& R, const Vector3& t, const S& scale) : R_(R), t_(t), s_(scale) {
    assert(scale > S(0));
  }
  Sim3(const Quaternion& q, const Vector3& t, const S& scale) : Sim3(SO3<S>(q), t, scale) {}
  Sim3(const Matrix3& R, const Vector3& t, const S& scale) : Sim3(SO3<S>(R), t, scale) {}
  /// A rigid transform as a similarity with scale 1.
  explicit Sim3(const SE3<S>& T) : R_(T.so3()), t_(T.translation()), s_(1) {}
  /// From a homogeneous 4x4 matrix [[s R, t], [0, 1]].
  explicit Sim3(const Matrix4& M) : t_(M.template topRightCorner<3, 1>()) {
    using std::sqrt;
    const Matrix3 sR = M.template topLeftCorner<3, 3>();
    s_ = sqrt(sR.squaredNorm() / S(3));
    R_ = SO3<S>(Matrix3(sR / s_));
  }

  static Sim3 identity() { return Sim3(); }

  /// exp([rho, phi, sigma]) = (exp(phi), W rho, e^sigma) with
  /// W = int_0^1 e^(sigma tau) exp(tau hat(phi)) dtau (accurate as sigma -> 0 and phi -> 0).
  static Sim3 exp(const Tangent& x) {
    using std::exp;
    const Vector3 rho = x.template head<3>();
    const Vector3 phi = x.template segment<3>(3);
    const S sigma = x(6);
    const lie::Sim3WCoefficients<S> w(sigma, phi.squaredNorm());
    const Vector3 pr = phi.cross(rho);
    return Sim3(SO3<S>::exp(phi), w.a * rho + w.b * pr + w.c * phi.cross(pr), exp(sigma),
                Unchecked{});
  }

  /// log(T) = [W^-1 t, log(R), log(s)], |phi| <= pi.
  Tangent log() const {
    using std::log;
    const Vector3 phi = R_.log();
    const S sigma = log(s_);
    const S theta2 = phi.squaredNorm();
    const lie::Sim3WCoefficients<S> w(sigma, theta2);
    // W^-1 = p I + q hat(phi) + r hat(phi)^2, from hat(phi)^3 = -theta^2 hat(phi).
    const S p = S(1) / w.a;
    const S e = w.a - theta2 * w.c;
    const S delta = e * e + theta2 * w.b * w.b;
    const S q = -w.b / delta;  // = -a b p / delta
    const S r = p * (w.b * w.b - w.c * e) / delta;
    const Vector3 pt = phi.cross(t_);
    Tangent x;
    x.template head<3>() = p * t_ + q * pt + r * phi.cross(pt);
    x.template segment<3>(3) = phi;
    x(6) = sigma;
    return x;
  }

  /// hat(x) = [[hat(phi) + sigma I, rho], [0, 0]] (4x4).
  static Matrix4 hat(const Tangent& x) {
    Matrix4 X = Matrix4::Zero();
    X.template topLeftCorner<3, 3>() =
        SO3<S>::hat(x.template segment<3>(3)) + x(6) * Matrix3::Identity();
    X.template topRightCorner<3, 1>() = x.template head<3>();
    return X;
  }
  /// vee(hat(x)) = x.
  static Tangent vee(const Matrix4& X) {
    Tangent x;
    x.template head<3>() = X.template topRightCorner<3, 1>();
    x.template segment<3>(3) = SO3<S>::vee(X.template topLeftCorner<3, 3>());
    x(6) = X.template topLeftCorner<3, 3>().trace() / S(3);
    return x;
  }
  /// Small adjoint ad(x) = [[hat(phi) + sigma I, hat(rho), -rho], [0, hat(phi), 0], [0, 0, 0]].
  static Adjoint ad(const Tangent& x) {
    const Vector3 rho = x.template head<3>();
    const Matrix3 P = SO3<S>::hat(x.template segment<3>(3));
    Adjoint A = Adjoint::Zero();
    A.template block<3, 3>(0, 0) = P + x(6) * Matrix3::Identity();
    A.template block<3, 3>(0, 3) = SO3<S>::hat(rho);
    A.template block<3, 1>(0, 6) = -rho;
    A.template block<3, 3>(3, 3) = P;
    return A;
  }

  Sim3 operator*(const Sim3& o) const {
    return Sim3(R_ * o.R_, t_ + s_ * (R_ * o.t_), s_ * o.s_, Unchecked{});
  }
  Sim3& operator*=(const Sim3& o) { return *this = *this * o; }
  /// Transforms a point: s R p + t.
  Vector3 operator*(const Vector3& p) const { return s_ * (R_ * p) + t_; }

  Sim3 inverse() const {
    const SO3<S> Ri = R_.inverse();
    const S si = S(1) / s_;
    return Sim3(Ri, -si * (Ri * t_), si, Unchecked{});
  }
  Matrix4 matrix() const {
    Matrix4 M = Matrix4::Identity();
    M.template topLeftCorner<3, 3>() = s_ * R_.matrix();
    M.template topRightCorner<3, 1>() = t_;
    return M;
  }
  /// Ad(T) = [[s R, hat(t) R, -t], [0, R, 0], [0, 0, 1]]: exp(Ad(T) x) = T exp(x) T^-1.
  Adjoint adjoint() const {
    const Matrix3 R = R_.matrix();
    Adjoint A = Adjoint::Zero();
    A.template block<3, 3>(0, 0) = s_ * R;
    A.template block<3, 3>(0, 3) = SO3<S>::hat(t_) * R;
    A.template block<3, 1>(0, 6) = -t_;
    A.template block<3, 3>(3, 3) = R;
    A(6, 6) = S(1);
    return A;
  }

  const SO3<S>& so3() const { return R_; }
  SO3<S>& so3() { return R_; }
  Matrix3 rotationMatrix() const { return R_.matrix(); }
  const Quaternion& quaternion() const { return R_.quaternion(); }
  const Vector3& translation() const { return t_; }
  Vector3& translation() { return t_; }
  const S& scale() const { return s_; }
  /// log(scale), the last tangent coordinate.
  S logScale() const {
    using std::log;
    return log(s_);
  }
  void setScale(const S& scale) {
    assert(scale > S(0));
    s_ = scale;
  }

  template <typename T>
  Sim3<T> cast() const {
    return Sim3<T>(R_.template cast<T>(), t_.template cast<T>(), T(s_));
  }

  /// Jl(x)^-1 = ad/(e^ad - 1) by its Bernoulli series up to ad^8; the truncation error is below
  /// |ad(x)|^10 / 4.8e7, i.e. negligible for the small residuals of a converging pose graph.
  static Adjoint leftJacobianInverse(const Tangent& x) { return jacobianInverseSeries(ad(x), -1); }
  /// Jr(x)^-1 = Jl(-x)^-1, same series and accuracy.
  static Adjoint rightJacobianInverse(const Tangent& x) { return jacobianInverseSeries(ad(x), 1); }
  /// d log(T * exp(d)) / dd at d = 0 ~ Jr(log T)^-1 (pose-graph residuals).
  Adjoint logJacobianRight() const { return rightJacobianInverse(log()); }
  /// d log(exp(d) * T) / dd at d = 0 ~ Jl(log T)^-1.
  Adjoint logJacobianLeft() const { return leftJacobianInverse(log()); }

  /// d (exp(d) * q) / dd at d = 0 = [I, -hat(q), q]. For (exp(d) * T) * p pass q = T * p.
  static PointJacobian actionJacobianAtIdentity(const Vector3& q) {
    PointJacobian J;
    J << Matrix3::Identity(), -SO3<S>::hat(q), q;
    return J;
  }
  /// d ((exp(d) * T) * p) / dd at d = 0.
  PointJacobian actionJacobianLeft(const Vector3& p) const {
    return actionJacobianAtIdentity(*this * p);
  }
  /// d ((T * exp(d)) * p) / dd at d = 0 = s R [I, -hat(p), p].
  PointJacobian actionJacobianRight(const Vector3& p) const {
    return actionJacobianPoint() * actionJacobianAtIdentity(p);
  }
  /// d (T * p) / dp = s R.
  Matrix3 actionJacobianPoint() const { return s_ * R_.matrix(); }

 private:
  struct Unchecked {};
  Sim3(const SO3<S>& R, const Vector3& t, const S& scale, Unchecked) : R_(R), t_(t), s_(scale) {}

  // I + sign ad/2 + ad^2/12 - ad^4/720 + ad^6/30240 - ad^8/1209600.
  static Adjoint jacobianInverseSeries(const Adjoint& A, int sign) {
    const Adjoint A2 = A * A;
    const Adjoint I = Adjoint::Identity();
    const Adjoint even =
        A2 * (I / S(12) + A2 * (-I / S(720) + A2 * (I / S(30240) - A2 / S(1209600))));
    return I + S(0.5 * sign) * A + even;
  }

  SO3<S> R_;
  Vector3 t_;
  S s_;
};

using Sim3d = Sim3<double>;
using Sim3f = Sim3<float>;

}  // namespace ldsm
