// SE(3): rigid transforms T = (R, t) acting as T * p = R p + t, templated on the scalar.
// Tangent order (everywhere in ldsm): x = [rho (translation part, 3), phi (rotation part, 3)],
// hat(x) = [[hat(phi), rho], [0, 0]]. Jacobian conventions as in so3.h:
//   exp(x + dx) ~ exp(Jl(x) dx) * exp(x) ~ exp(x) * exp(Jr(x) dx),   Jr(x) = Jl(-x).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "ldsm/types.h"
#include "math/lie_coefficients.h"
#include "math/so3.h"

namespace ldsm {

template <typename S>
class SE3 {
 public:
  using Scalar = S;
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  using Matrix3 = Eigen::Matrix<S, 3, 3>;
  using Matrix4 = Eigen::Matrix<S, 4, 4>;
  using Matrix3x4 = Eigen::Matrix<S, 3, 4>;
  using Quaternion = Eigen::Quaternion<S>;
  using Tangent = Eigen::Matrix<S, 6, 1>;  ///< [rho (translation), phi (rotation)]
  using Adjoint = Eigen::Matrix<S, 6, 6>;
  using PointJacobian = Eigen::Matrix<S, 3, 6>;
  static constexpr int kDoF = 6;

  /// Identity transform.
  SE3() : t_(Vector3::Zero()) {}
  SE3(const SO3<S>& R, const Vector3& t) : R_(R), t_(t) {}
  /// From a quaternion (normalised here) and a translation.
  SE3(const Quaternion& q, const Vector3& t) : R_(q), t_(t) {}
  /// From a rotation matrix (not checked, see SO3) and a translation.
  SE3(const Matrix3& R, const Vector3& t) : R_(R), t_(t) {}
  /// From a homogeneous 4x4 matrix [[R, t], [0, 1]] (the last row is ignored).
  explicit SE3(const Matrix4& T)
      : R_(Matrix3(T.template topLeftCorner<3, 3>())), t_(T.template topRightCorner<3, 1>()) {}

  static SE3 identity() { return SE3(); }
  /// From an ldsm::Pose (quaternion normalised).
  static SE3 fromPose(const Pose& p) {
    return SE3(p.rotation.template cast<S>(), p.translation.template cast<S>());
  }
  /// To an ldsm::Pose (double). Not available for autodiff scalars.
  Pose toPose() const {
    Pose p;
    p.rotation = R_.quaternion().template cast<double>();
    p.translation = t_.template cast<double>();
    return p;
  }

  /// exp([rho, phi]) = (exp(phi), Jl(phi) rho) with the SO3 left Jacobian Jl.
  static SE3 exp(const Tangent& x) {
    const Vector3 rho = x.template head<3>();
    const Vector3 phi = x.template tail<3>();
    const S theta2 = phi.squaredNorm();
    const Vector3 pr = phi.cross(rho);
    const Vector3 t = rho + lie::oneMinusCosOverTheta2(theta2) * pr +
                      lie::thetaMinusSinOverTheta3(theta2) * phi.cross(pr);
    return SE3(SO3<S>::exp(phi), t);
  }

  /// log(T) = [Jl(phi)^-1 t, phi] with phi = log(R), |phi| <= pi.
  Tangent log() const {
    const Vector3 phi = R_.log();
    const S theta2 = phi.squaredNorm();
    const Vector3 pt = phi.cross(t_);
    Tangent x;
    x.template head<3>() =
        t_ - S(0.5) * pt + lie::inverseJacobianCoefficient(theta2) * phi.cross(pt);
    x.template tail<3>() = phi;
    return x;
  }

  /// hat(x) = [[hat(phi), rho], [0, 0]] (4x4).
  static Matrix4 hat(const Tangent& x) {
    Matrix4 X = Matrix4::Zero();
    X.template topLeftCorner<3, 3>() = SO3<S>::hat(x.template tail<3>());
    X.template topRightCorner<3, 1>() = x.template head<3>();
    return X;
  }
  /// vee(hat(x)) = x.
  static Tangent vee(const Matrix4& X) {
    Tangent x;
    x.template head<3>() = X.template topRightCorner<3, 1>();
    x.template tail<3>() = SO3<S>::vee(X.template topLeftCorner<3, 3>());
    return x;
  }
  /// Small adjoint ad(x) = [[hat(phi), hat(rho)], [0, hat(phi)]]: ad(x) y = vee([hat(x), hat(y)]).
  static Adjoint ad(const Tangent& x) {
    const Matrix3 P = SO3<S>::hat(x.template tail<3>());
    Adjoint A;
    A << P, SO3<S>::hat(x.template head<3>()), Matrix3::Zero(), P;
    return A;
  }

  SE3 operator*(const SE3& o) const { return SE3(R_ * o.R_, t_ + R_ * o.t_); }
  SE3& operator*=(const SE3& o) { return *this = *this * o; }
  /// Transforms a point: R p + t.
  Vector3 operator*(const Vector3& p) const { return R_ * p + t_; }

  SE3 inverse() const {
    const SO3<S> Ri = R_.inverse();
    return SE3(Ri, -(Ri * t_));
  }
  Matrix4 matrix() const {
    Matrix4 T = Matrix4::Identity();
    T.template topLeftCorner<3, 3>() = R_.matrix();
    T.template topRightCorner<3, 1>() = t_;
    return T;
  }
  Matrix3x4 matrix3x4() const {
    Matrix3x4 T;
    T.template leftCols<3>() = R_.matrix();
    T.col(3) = t_;
    return T;
  }
  /// Ad(T) = [[R, hat(t) R], [0, R]]: exp(Ad(T) x) = T exp(x) T^-1.
  Adjoint adjoint() const {
    const Matrix3 R = R_.matrix();
    Adjoint A;
    A << R, SO3<S>::hat(t_) * R, Matrix3::Zero(), R;
    return A;
  }

  const SO3<S>& so3() const { return R_; }
  SO3<S>& so3() { return R_; }
  Matrix3 rotationMatrix() const { return R_.matrix(); }
  const Quaternion& quaternion() const { return R_.quaternion(); }
  const Vector3& translation() const { return t_; }
  Vector3& translation() { return t_; }

  template <typename T>
  SE3<T> cast() const {
    return SE3<T>(R_.template cast<T>(), t_.template cast<T>());
  }

  /// The coupling block Q(rho, phi) of the SE3 left Jacobian (Barfoot's notation).
  static Matrix3 jacobianQ(const Vector3& rho, const Vector3& phi) {
    const S theta2 = phi.squaredNorm();
    const Matrix3 P = SO3<S>::hat(phi);
    const Matrix3 Rh = SO3<S>::hat(rho);
    const Matrix3 PR = P * Rh;
    const Matrix3 RP = Rh * P;
    const Matrix3 PRP = PR * P;
    return S(0.5) * Rh + lie::thetaMinusSinOverTheta3(theta2) * (PR + RP + PRP) +
           lie::se3QCoefficient2(theta2) * (P * PR + RP * P - S(3) * PRP) +
           lie::se3QCoefficient3(theta2) * (PRP * P + P * PRP);
  }
  /// Left Jacobian Jl(x) = [[Jl(phi), Q], [0, Jl(phi)]].
  static Adjoint leftJacobian(const Tangent& x) {
    const Vector3 phi = x.template tail<3>();
    const Matrix3 J = SO3<S>::leftJacobian(phi);
    Adjoint A;
    A << J, jacobianQ(x.template head<3>(), phi), Matrix3::Zero(), J;
    return A;
  }
  /// Jl(x)^-1 = [[Jl^-1, -Jl^-1 Q Jl^-1], [0, Jl^-1]] (SO3 blocks of phi); |phi| <= pi.
  static Adjoint leftJacobianInverse(const Tangent& x) {
    const Vector3 phi = x.template tail<3>();
    const Matrix3 Ji = SO3<S>::leftJacobianInverse(phi);
    Adjoint A;
    A << Ji, -Ji * jacobianQ(x.template head<3>(), phi) * Ji, Matrix3::Zero(), Ji;
    return A;
  }
  static Adjoint rightJacobian(const Tangent& x) { return leftJacobian(Tangent(-x)); }
  static Adjoint rightJacobianInverse(const Tangent& x) { return leftJacobianInverse(Tangent(-x)); }
  /// d log(T * exp(d)) / dd at d = 0 = Jr(log T)^-1 (pose-graph residuals).
  Adjoint logJacobianRight() const { return rightJacobianInverse(log()); }
  /// d log(exp(d) * T) / dd at d = 0 = Jl(log T)^-1.
  Adjoint logJacobianLeft() const { return leftJacobianInverse(log()); }

  /// d (exp(d) * q) / dd at d = 0 = [I, -hat(q)]. For (exp(d) * T) * p pass q = T * p.
  static PointJacobian actionJacobianAtIdentity(const Vector3& q) {
    PointJacobian J;
    J << Matrix3::Identity(), -SO3<S>::hat(q);
    return J;
  }
  /// d ((exp(d) * T) * p) / dd at d = 0.
  PointJacobian actionJacobianLeft(const Vector3& p) const {
    return actionJacobianAtIdentity(*this * p);
  }
  /// d ((T * exp(d)) * p) / dd at d = 0 = R [I, -hat(p)].
  PointJacobian actionJacobianRight(const Vector3& p) const {
    return R_.matrix() * actionJacobianAtIdentity(p);
  }
  /// d (T * p) / dp = R.
  Matrix3 actionJacobianPoint() const { return R_.matrix(); }

 private:
  SO3<S> R_;
  Vector3 t_;
};

using SE3d = SE3<double>;
using SE3f = SE3<float>;

/// Interpolates a trajectory between two poses: rotation along the SO3 geodesic, translation on the
/// straight line (1 - alpha) t0 + alpha t1, which is what ground-truth resampling wants for
/// camera-to-world poses (the camera centre moves linearly). alpha = 0 gives T0, 1 gives T1.
template <typename S>
SE3<S> interpolate(const SE3<S>& T0, const SE3<S>& T1, const typename SE3<S>::Scalar& alpha) {
  return SE3<S>(interpolate(T0.so3(), T1.so3(), alpha),
                (S(1) - alpha) * T0.translation() + alpha * T1.translation());
}

/// Interpolates along the SE3 geodesic (screw motion): T0 * exp(alpha * log(T0^-1 T1)).
template <typename S>
SE3<S> interpolateGeodesic(const SE3<S>& T0, const SE3<S>& T1,
                           const typename SE3<S>::Scalar& alpha) {
  return T0 * SE3<S>::exp(alpha * (T0.inverse() * T1).log());
}

}  // namespace ldsm
