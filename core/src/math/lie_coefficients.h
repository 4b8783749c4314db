// Scalar coefficient functions of the Lie-group formulas (SO3, SE3, Sim3), each evaluated so that
// it stays accurate at the removable singularities: a Taylor series for small angles and, for the
// Sim(3) translation coefficients, for small log-scales too. Every function is templated on the
// scalar (double, float, ceres::Jet) and takes the squared angle theta2 = |w|^2, so that autodiff
// through theta = 0 never evaluates sqrt(0).
#pragma once

#include <cmath>
#include <type_traits>

namespace ldsm::lie {

/// Below this squared angle (theta < 0.01 rad) the functions without cancellation in their closed
/// form switch to a short series (terms up to theta^4, truncation error < 1e-16), only to avoid
/// 0/0 and sqrt(0) (whose derivative is infinite for autodiff scalars).
inline constexpr double kSmallAngleSq = 1e-4;
/// The closed forms of (theta - sin)/theta^3 and similar lose eps/theta^2 (or eps/theta^4) of
/// relative accuracy to cancellation, so those use their Taylor series (Horner, enough terms for
/// double precision) up to theta = 1 rad (2 rad for the theta^-5 one).
inline constexpr double kSeriesAngleSq = 1.0;
inline constexpr double kWideSeriesAngleSq = 4.0;
/// The Sim3 translation coefficients use a series in theta^2 (terms to theta^12, moments of
/// e^(sigma t)) up to theta = 0.3 rad; above it their closed forms lose at most ~6 eps / theta^2.
inline constexpr double kSim3SeriesAngleSq = 0.09;

constexpr double factorial(int n) {
  double f = 1;
  for (int i = 2; i <= n; ++i) f *= i;
  return f;
}

/// sum_k c[k] x^k (Horner).
template <typename S, int N>
inline S polynomial(const S& x, const double (&c)[N]) {
  S r(c[N - 1]);
  for (int k = N - 2; k >= 0; --k) r = r * x + S(c[k]);
  return r;
}

// Taylor coefficients (in theta^2) of the functions below; the first left-out term is < 1e-17
// relative at the switching angle.
inline constexpr double kThetaMinusSinSeries[] = {
    1 / factorial(3),   -1 / factorial(5), 1 / factorial(7),   -1 / factorial(9), 1 / factorial(11),
    -1 / factorial(13), 1 / factorial(15), -1 / factorial(17), 1 / factorial(19)};
inline constexpr double kInverseJacobianSeries[] = {  // (-1)^(n+1) B_2n / (2n)!, n = 1..11
    1.0 / 12.0,
    1.0 / 720.0,
    1.0 / 30240.0,
    1.0 / 1209600.0,
    1.0 / 47900160.0,
    691.0 / 1307674368000.0,
    1.0 / 74724249600.0,
    3617.0 / 10670622842880000.0,
    43867.0 / 5109094217170944000.0,
    174611.0 / 802857662698291200000.0,
    77683.0 / 14101100039391805440000.0};
inline constexpr double kQ2Series[] = {  // (-1)^m / (2m)!, m = 2..10
    1 / factorial(4),   -1 / factorial(6),  1 / factorial(8),
    -1 / factorial(10), 1 / factorial(12),  -1 / factorial(14),
    1 / factorial(16),  -1 / factorial(18), 1 / factorial(20)};
inline constexpr double kQ3Series[] = {  // (-1)^m (m - 1) / (2m + 1)!, m = 2..13
    1 / factorial(5),  -2 / factorial(7),   3 / factorial(9),   -4 / factorial(11),
    5 / factorial(13), -6 / factorial(15),  7 / factorial(17),  -8 / factorial(19),
    9 / factorial(21), -10 / factorial(23), 11 / factorial(25), -12 / factorial(27)};

/// True when theta2 is in the range where the series are used.
template <typename S>
inline bool isSmallAngle(const S& theta2) {
  return theta2 < S(kSmallAngleSq);
}

/// sin(theta/2) / theta: imaginary factor of the quaternion exp(w) = (cos(theta/2), f * w).
template <typename S>
inline S sinHalfOverTheta(const S& theta2) {
  using std::sin;
  using std::sqrt;
  if (isSmallAngle(theta2)) {
    return S(0.5) - theta2 / S(48) + theta2 * theta2 / S(3840);
  }
  const S theta = sqrt(theta2);
  return sin(theta / S(2)) / theta;
}

/// cos(theta/2): real part of the quaternion exp(w).
template <typename S>
inline S cosHalf(const S& theta2) {
  using std::cos;
  using std::sqrt;
  if (isSmallAngle(theta2)) {
    return S(1) - theta2 / S(8) + theta2 * theta2 / S(384);
  }
  return cos(sqrt(theta2) / S(2));
}

/// (1 - cos(theta)) / theta^2: coefficient of hat(w) in the SO3 left Jacobian.
template <typename S>
inline S oneMinusCosOverTheta2(const S& theta2) {
  using std::sin;
  using std::sqrt;
  if (isSmallAngle(theta2)) {
    return S(0.5) - theta2 / S(24) + theta2 * theta2 / S(720);
  }
  const S sh = sin(sqrt(theta2) / S(2));
  return S(2) * sh * sh / theta2;  // 1 - cos = 2 sin^2(theta/2): no cancellation
}

/// (theta - sin(theta)) / theta^3: coefficient of hat(w)^2 in the SO3 left Jacobian.
template <typename S>
inline S thetaMinusSinOverTheta3(const S& theta2) {
  using std::sin;
  using std::sqrt;
  if (theta2 < S(kSeriesAngleSq)) return polynomial(theta2, kThetaMinusSinSeries);
  const S theta = sqrt(theta2);
  return (theta - sin(theta)) / (theta2 * theta);
}

/// 1/theta^2 - cot(theta/2) / (2 theta): coefficient of hat(w)^2 in the inverse SO3 Jacobians.
/// Finite on [0, pi] (1/pi^2 at pi).
template <typename S>
inline S inverseJacobianCoefficient(const S& theta2) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  if (theta2 < S(kSeriesAngleSq)) return polynomial(theta2, kInverseJacobianSeries);
  const S theta = sqrt(theta2);
  const S half = theta / S(2);
  return (S(1) - theta * cos(half) / (S(2) * sin(half))) / theta2;
}

/// (theta^2 + 2 cos(theta) - 2) / (2 theta^4): a coefficient of the SE3 Jacobian block Q.
template <typename S>
inline S se3QCoefficient2(const S& theta2) {
  using std::sin;
  using std::sqrt;
  if (theta2 < S(kSeriesAngleSq)) return polynomial(theta2, kQ2Series);
  const S sh = sin(sqrt(theta2) / S(2));
  return (theta2 - S(4) * sh * sh) / (S(2) * theta2 * theta2);
}

/// (2 theta - 3 sin(theta) + theta cos(theta)) / (2 theta^5): a coefficient of the SE3 block Q.
template <typename S>
inline S se3QCoefficient3(const S& theta2) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  if (theta2 < S(kWideSeriesAngleSq)) return polynomial(theta2, kQ3Series);
  const S theta = sqrt(theta2);
  return (S(2) * theta - S(3) * sin(theta) + theta * cos(theta)) / (S(2) * theta2 * theta2 * theta);
}

/// 2 atan2(n, w) / n for a unit quaternion (w, v) with w >= 0 and n = |v|, given n2 = n^2: the
/// factor that maps the vector part of the quaternion to the rotation vector.
template <typename S>
inline S quaternionLogFactor(const S& n2, const S& w) {
  using std::atan2;
  using std::sqrt;
  if (isSmallAngle(n2)) {
    // atan(x) = x - x^3/3 + x^5/5 - x^7/7 with x = n / w (w ~ 1 here; x^8/9 < 1e-17 left out).
    const S x2 = n2 / (w * w);
    return S(2) / w * (S(1) - x2 * (S(1) / S(3) - x2 * (S(1) / S(5) - x2 / S(7))));
  }
  const S n = sqrt(n2);
  return S(2) * atan2(n, w) / n;
}

/// The integrals I_k(sigma) = int_0^1 tau^k exp(sigma tau) dtau for k = 0..N-1, used by the Sim3
/// translation coefficients. A power series for |sigma| < 1 (exact at sigma = 0, also for the
/// derivatives of autodiff scalars), the upward recurrence I_k = (e^sigma - k I_(k-1)) / sigma
/// otherwise. I_0 = (e^sigma - 1) / sigma.
template <typename S, int N>
struct ExpMoments {
  S I[N];

  explicit ExpMoments(const S& sigma) {
    using std::abs;
    using std::exp;
    if (abs(sigma) < S(1)) {
      for (int k = 0; k < N; ++k) I[k] = S(0);
      S term(1);  // sigma^j / j!; 20 terms leave < 1e-19
      for (int j = 0; j < 20; ++j) {
        for (int k = 0; k < N; ++k) I[k] += term * S(1.0 / (k + j + 1));
        term = term * sigma / S(j + 1);
        // Plain scalars stop once the terms vanish; autodiff scalars keep every term because a
        // zero value can still carry a derivative.
        if constexpr (std::is_floating_point_v<S>) {
          if (abs(term) < S(1e-18)) break;
        }
      }
    } else {
      const S es = exp(sigma);
      I[0] = (es - S(1)) / sigma;
      for (int k = 1; k < N; ++k) I[k] = (es - S(k) * I[k - 1]) / sigma;
    }
  }
};

/// Coefficients of W(sigma, w) = a I + b hat(w) + c hat(w)^2 = int_0^1 e^(sigma tau) exp(tau
/// hat(w)) dtau, the matrix that maps the Sim3 tangent translation to the group translation.
template <typename S>
struct Sim3WCoefficients {
  S a, b, c;

  Sim3WCoefficients(const S& sigma, const S& theta2) {
    using std::cos;
    using std::exp;
    using std::expm1;
    using std::sin;
    using std::sqrt;
    if (theta2 < S(kSim3SeriesAngleSq)) {
      // b = int e^(st) sin(theta t)/theta dt = sum_k (-theta2)^k I_(2k+1) / (2k+1)!,
      // c = int e^(st) (1 - cos(theta t))/theta^2 dt = sum_k (-theta2)^k I_(2k+2) / (2k+2)!.
      // Rounding amplified in the high moments (|sigma| >= 1) is damped by theta^2k / (2k)!.
      const ExpMoments<S, 15> m(sigma);
      a = m.I[0];
      b = S(0);
      c = S(0);
      for (int k = 6; k >= 0; --k) {
        b = b * (-theta2) + m.I[2 * k + 1] * S(1 / factorial(2 * k + 1));
        c = c * (-theta2) + m.I[2 * k + 2] * S(1 / factorial(2 * k + 2));
      }
      return;
    }
    // Closed forms from int_0^1 e^(z t) dt = (e^z - 1) / z with z = sigma + i theta.
    const S theta = sqrt(theta2);
    const S s = exp(sigma);
    const S st = sin(theta);
    const S sh = sin(theta / S(2));
    const S r2 = sigma * sigma + theta2;
    a = ExpMoments<S, 1>(sigma).I[0];
    // 1 - s cos(theta) = (1 - s) + 2 s sin^2(theta/2), with 1 - s = -expm1(sigma) exactly.
    const S one_minus_scos = S(2) * s * sh * sh - expm1(sigma);
    b = (sigma * s * st + theta * one_minus_scos) / (theta * r2);
    const S re = (theta * s * st - sigma * one_minus_scos) / r2;  // int e^(st) cos(theta t)
    c = (a - re) / theta2;
  }
};

}  // namespace ldsm::lie
