#include "loop/sim3_refinement.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include <ceres/ceres.h>
#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "ldsm/error.h"

namespace ldsm::loop {
namespace {

// Both residuals see the point already moved by the current estimate S0, p0 = S0 p, and are
// functions of a left increment delta: S = exp(delta) * S0.
template <typename T>
Eigen::Matrix<T, 3, 1> movedPoint(const T* delta, const Eigen::Vector3d& p0) {
  const Eigen::Map<const Eigen::Matrix<T, 7, 1>> d(delta);
  return Sim3<T>::exp(d) * p0.cast<T>();
}

struct ReprojectionCost {
  Eigen::Vector3d p0;
  Eigen::Vector2d pixel;
  double fx, fy, cx, cy;
  Eigen::Matrix2d sqrt_info;  // whitening of the pixel error (upper triangular)

  template <typename T>
  bool operator()(const T* delta, T* r) const {
    const Eigen::Matrix<T, 3, 1> x = movedPoint(delta, p0);
    if (!(x.z() > T(1e-12))) return false;  // behind the camera: LM rejects this step
    const T e0 = T(fx) * x.x() / x.z() + T(cx) - T(pixel.x());
    const T e1 = T(fy) * x.y() / x.z() + T(cy) - T(pixel.y());
    r[0] = T(sqrt_info(0, 0)) * e0 + T(sqrt_info(0, 1)) * e1;
    r[1] = T(sqrt_info(1, 0)) * e0 + T(sqrt_info(1, 1)) * e1;
    return true;
  }
};

struct PointCost {
  Eigen::Vector3d p0;
  Eigen::Vector3d q;
  Eigen::Matrix3d sqrt_info;  // whitening of the 3D error

  template <typename T>
  bool operator()(const T* delta, T* r) const {
    const Eigen::Matrix<T, 3, 1> x = movedPoint(delta, p0);
    const Eigen::Matrix<T, 3, 1> e = x - q.cast<T>();
    for (int i = 0; i < 3; ++i)
      r[i] = T(sqrt_info(i, 0)) * e(0) + T(sqrt_info(i, 1)) * e(1) + T(sqrt_info(i, 2)) * e(2);
    return true;
  }
};

// The reprojection error and the depth error along the current camera's axis, jointly whitened:
// for a match with a current depth the two share the candidate point's depth error.
struct PixelDepthCost {
  Eigen::Vector3d p0;
  Eigen::Vector2d pixel;
  double depth;  // z of the current feature's 3D point
  double fx, fy, cx, cy;
  Eigen::Matrix3d sqrt_info;

  template <typename T>
  bool operator()(const T* delta, T* r) const {
    const Eigen::Matrix<T, 3, 1> x = movedPoint(delta, p0);
    if (!(x.z() > T(1e-12))) return false;
    const T e[3] = {T(fx) * x.x() / x.z() + T(cx) - T(pixel.x()),
                    T(fy) * x.y() / x.z() + T(cy) - T(pixel.y()), x.z() - T(depth)};
    for (int i = 0; i < 3; ++i)
      r[i] = T(sqrt_info(i, 0)) * e[0] + T(sqrt_info(i, 1)) * e[1] + T(sqrt_info(i, 2)) * e[2];
    return true;
  }
};

// L^T with L L^T = inverse of a symmetric positive definite covariance: r_w = L^T r has unit
// covariance.
template <int N>
Eigen::Matrix<double, N, N> sqrtInformation(const Eigen::Matrix<double, N, N>& covariance) {
  const Eigen::Matrix<double, N, N> info = covariance.inverse();
  return Eigen::LLT<Eigen::Matrix<double, N, N>>(info).matrixL().transpose();
}

struct Whitened {
  bool in_front = false;
  double chi2_2d = 0.0;   // squared whitened reprojection error
  double chi2_3d = -1.0;  // squared whitened 3D error, < 0 without current depth
  double pixel_error2 = 0.0;
};

class Refiner {
 public:
  Refiner(const std::vector<Sim3Correspondence>& c, const PinholeIntrinsics& cam,
          const Sim3RefinementSettings& s)
      : c_(c), cam_(cam), s_(s), q_(c.size()) {
    for (std::size_t i = 0; i < c.size(); ++i) {
      if (!hasCurrentDepth(c[i])) continue;
      const Eigen::Vector3d ray((c[i].pixel_current.x() - cam.cx) / cam.fx,
                                (c[i].pixel_current.y() - cam.cy) / cam.fy, 1.0);
      q_[i] = ray / c[i].idepth_current;
    }
  }

  // The errors' covariances at S, from three sources: the current feature's pixel (pixel_sigma),
  // the current feature's depth and the candidate point's depth (each depth_relative_sigma,
  // relative, along its own ray; the candidate's moves S p along S's image of that ray). A match
  // with a current depth gives the reprojection error and the depth error along the current
  // axis, whitened jointly (they share the candidate's depth error; the lateral part of a 3D
  // error would repeat the pixel); without a current depth, the reprojection error alone.
  Eigen::Matrix<double, 2, 3> projectionJacobian(const Eigen::Vector3d& x) const {
    Eigen::Matrix<double, 2, 3> dpi;
    const double iz = 1.0 / std::max(x.z(), 1e-12);
    dpi << cam_.fx * iz, 0.0, -cam_.fx * x.x() * iz * iz, 0.0, cam_.fy * iz,
        -cam_.fy * x.y() * iz * iz;
    return dpi;
  }
  Eigen::Matrix2d sqrtInfo2d(std::size_t i, const Sim3d& S) const {
    const Eigen::Vector3d x = S * c_[i].point_candidate;
    const Eigen::Vector2d J = projectionJacobian(x) * (x - S.translation());
    const double sd = s_.depth_relative_sigma;
    const Eigen::Matrix2d cov =
        s_.pixel_sigma * s_.pixel_sigma * Eigen::Matrix2d::Identity() + sd * sd * J * J.transpose();
    return sqrtInformation<2>(cov);
  }
  Eigen::Matrix3d sqrtInfoPixelDepth(std::size_t i, const Sim3d& S) const {
    const Eigen::Vector3d x = S * c_[i].point_candidate;
    const Eigen::Vector3d along = x - S.translation();
    Eigen::Vector3d a_cand;  // candidate depth error
    a_cand << projectionJacobian(x) * along, along.z();
    const double sd = s_.depth_relative_sigma;
    Eigen::Matrix3d cov = sd * sd * a_cand * a_cand.transpose();
    cov.topLeftCorner<2, 2>() += s_.pixel_sigma * s_.pixel_sigma * Eigen::Matrix2d::Identity();
    cov(2, 2) += sd * sd * q_[i].z() * q_[i].z();
    return sqrtInformation<3>(cov);
  }
  // 3D error alone (reprojection_for_depth_matches off, LDO's split): the pixel error moves the
  // current point sideways.
  Eigen::Matrix3d sqrtInfo3d(std::size_t i, const Sim3d& S) const {
    const Eigen::Vector3d x = S * c_[i].point_candidate;
    const Eigen::Vector3d along = x - S.translation();
    const Eigen::Vector3d& q = q_[i];
    const double sd = s_.depth_relative_sigma;
    Eigen::Matrix<double, 3, 2> dq_du = Eigen::Matrix<double, 3, 2>::Zero();
    dq_du(0, 0) = q.z() / cam_.fx;
    dq_du(1, 1) = q.z() / cam_.fy;
    const Eigen::Matrix3d cov = sd * sd * (q * q.transpose() + along * along.transpose()) +
                                s_.pixel_sigma * s_.pixel_sigma * dq_du * dq_du.transpose();
    return sqrtInformation<3>(cov);
  }

  Whitened evaluate(std::size_t i, const Sim3d& S) const {
    Whitened w;
    const Eigen::Vector3d x = S * c_[i].point_candidate;
    w.in_front = x.z() > 1e-12;
    Eigen::Vector2d e = Eigen::Vector2d::Zero();
    if (w.in_front) {
      const Eigen::Vector2d u(cam_.fx * x.x() / x.z() + cam_.cx, cam_.fy * x.y() / x.z() + cam_.cy);
      e = u - c_[i].pixel_current;
      w.pixel_error2 = e.squaredNorm();
      w.chi2_2d = (sqrtInfo2d(i, S) * e).squaredNorm();
    }
    if (hasCurrentDepth(c_[i])) {
      if (s_.reprojection_for_depth_matches) {
        const Eigen::Vector3d e3(e.x(), e.y(), x.z() - q_[i].z());
        w.chi2_3d = (sqrtInfoPixelDepth(i, S) * e3).squaredNorm();
      } else {
        w.chi2_3d = (sqrtInfo3d(i, S) * (x - q_[i])).squaredNorm();
      }
    }
    return w;
  }

  // A match with a current depth is tested on its 3-dimensional error, one without on its pixel.
  bool isInlier(const Whitened& w) const {
    if (!w.in_front) return false;
    if (w.chi2_3d < 0.0) return w.chi2_2d < s_.chi2_2d;
    return w.chi2_3d < s_.chi2_3d;
  }

  // The cost of match i linearised at S (owned by the caller), and its dimension.
  ceres::CostFunction* cost(std::size_t i, const Sim3d& S, int* dim) const {
    const Eigen::Vector3d p0 = S * c_[i].point_candidate;
    if (!hasCurrentDepth(c_[i])) {
      *dim = 2;
      return new ceres::AutoDiffCostFunction<ReprojectionCost, 2, 7>(new ReprojectionCost{
          p0, c_[i].pixel_current, cam_.fx, cam_.fy, cam_.cx, cam_.cy, sqrtInfo2d(i, S)});
    }
    *dim = 3;
    if (s_.reprojection_for_depth_matches) {
      return new ceres::AutoDiffCostFunction<PixelDepthCost, 3, 7>(
          new PixelDepthCost{p0, c_[i].pixel_current, q_[i].z(), cam_.fx, cam_.fy, cam_.cx, cam_.cy,
                             sqrtInfoPixelDepth(i, S)});
    }
    return new ceres::AutoDiffCostFunction<PointCost, 3, 7>(
        new PointCost{p0, q_[i], sqrtInfo3d(i, S)});
  }

  // One Levenberg-Marquardt solve over the active correspondences; returns the new estimate.
  // J^T J and r^T r of the active correspondences' whitened residuals at S (no robust weights:
  // the active ones passed the chi-square tests), with the number of scalar residuals.
  void normalEquations(const Sim3d& S, const std::vector<std::uint8_t>& active,
                       Eigen::Matrix<double, 7, 7>& H, double& r2, int& m) const {
    H.setZero();
    r2 = 0.0;
    m = 0;
    const double delta[7] = {0, 0, 0, 0, 0, 0, 0};
    const double* params[1] = {delta};
    auto add = [&](const ceres::CostFunction& cost, int dim) {
      double r[3];
      double j[21];
      double* jac[1] = {j};
      if (!cost.Evaluate(params, r, jac)) return;
      const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 7, Eigen::RowMajor>> J(j, dim,
                                                                                          7);
      const Eigen::Map<const Eigen::VectorXd> rv(r, dim);
      H += J.transpose() * J;
      r2 += rv.squaredNorm();
      m += dim;
    };
    for (std::size_t i = 0; i < c_.size(); ++i) {
      if (!active[i]) continue;
      int dim = 0;
      const std::unique_ptr<ceres::CostFunction> c(cost(i, S, &dim));
      add(*c, dim);
    }
  }

  Sim3d solve(const Sim3d& S0, const std::vector<std::uint8_t>& active, bool* ok) const {
    double delta[7] = {0, 0, 0, 0, 0, 0, 0};
    ceres::Problem::Options popt;
    popt.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(popt);
    ceres::HuberLoss loss_2d(s_.huber_2d);
    ceres::HuberLoss loss_3d(s_.huber_3d);
    for (std::size_t i = 0; i < c_.size(); ++i) {
      if (!active[i]) continue;
      int dim = 0;
      ceres::CostFunction* c = cost(i, S0, &dim);
      problem.AddResidualBlock(c, dim == 2 ? &loss_2d : &loss_3d, delta);
    }
    ceres::Solver::Options options;
    options.linear_solver_type = ceres::DENSE_QR;
    options.minimizer_type = ceres::TRUST_REGION;
    options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
    options.max_num_iterations = s_.max_iterations;
    options.num_threads = 1;
    options.logging_type = ceres::SILENT;
    options.minimizer_progress_to_stdout = false;
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    const Eigen::Map<const Eigen::Matrix<double, 7, 1>> d(delta);
    *ok = summary.IsSolutionUsable() && d.allFinite();
    return *ok ? Sim3d::exp(d) * S0 : S0;
  }

 private:
  const std::vector<Sim3Correspondence>& c_;
  const PinholeIntrinsics& cam_;
  const Sim3RefinementSettings& s_;
  std::vector<Eigen::Vector3d> q_;  // 3D point of the current keyframe (when it has depth)
};

void checkInput(const std::vector<Sim3Correspondence>& c, const PinholeIntrinsics& cam,
                const Sim3d& initial, const Sim3RefinementSettings& s) {
  if (!(cam.fx > 0 && cam.fy > 0 && std::isfinite(cam.fx) && std::isfinite(cam.fy) &&
        std::isfinite(cam.cx) && std::isfinite(cam.cy))) {
    throw InputError("Sim(3) refinement: invalid pinhole intrinsics (fx, fy must be finite, > 0)");
  }
  if (!(s.pixel_sigma > 0 && s.depth_relative_sigma > 0 && s.huber_2d > 0 && s.huber_3d > 0 &&
        s.chi2_2d > 0 && s.chi2_3d > 0 && s.rounds >= 1 && s.max_iterations >= 1)) {
    throw InputError("Sim(3) refinement: settings out of range (sigmas, thresholds must be > 0)");
  }
  if (!initial.matrix().allFinite() || !(initial.scale() > 0)) {
    throw InputError("Sim(3) refinement: initial transform is not finite");
  }
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (!c[i].point_candidate.allFinite() || !c[i].pixel_current.allFinite()) {
      throw InputError("Sim(3) refinement: correspondence " + std::to_string(i) + " is not finite");
    }
  }
}

}  // namespace

Sim3RefinementResult refineSim3(const std::vector<Sim3Correspondence>& correspondences,
                                const PinholeIntrinsics& camera_current, const Sim3d& initial,
                                const Sim3RefinementSettings& settings,
                                const std::vector<std::uint8_t>* initial_inliers) {
  checkInput(correspondences, camera_current, initial, settings);
  const std::size_t n = correspondences.size();
  const Refiner refiner(correspondences, camera_current, settings);
  Sim3RefinementResult result;
  result.S_current_candidate = initial;
  result.inlier.assign(n, 0);

  // The first round takes the given inliers (or everything) in front of the camera, with Huber
  // norms; later rounds only the inliers of the previous one.
  if (initial_inliers != nullptr && initial_inliers->size() != n) {
    throw InputError("Sim(3) refinement: " + std::to_string(initial_inliers->size()) +
                     " initial inlier flags for " + std::to_string(n) + " correspondences");
  }
  std::vector<std::uint8_t> active(n, 0);
  int n_active = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const bool wanted = initial_inliers == nullptr || (*initial_inliers)[i] != 0;
    active[i] = wanted && refiner.evaluate(i, initial).in_front;
    n_active += active[i];
  }
  Sim3d S = initial;
  for (int round = 0; round < settings.rounds; ++round) {
    if (n_active < 3) return result;
    bool ok = false;
    S = refiner.solve(S, active, &ok);
    if (!ok) return result;
    n_active = 0;
    for (std::size_t i = 0; i < n; ++i) {
      active[i] = refiner.isInlier(refiner.evaluate(i, S));
      n_active += active[i];
    }
  }

  result.success = n_active > 0;
  result.S_current_candidate = S;
  result.inlier = active;
  double sum_e2 = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!active[i]) continue;
    const Whitened w = refiner.evaluate(i, S);
    sum_e2 += w.pixel_error2;
    if (w.chi2_3d >= 0.0) {
      ++result.inliers_3d;
    } else {
      ++result.inliers_2d;
    }
  }
  if (n_active > 0) result.rms_reprojection_px = std::sqrt(sum_e2 / n_active);
  Eigen::Matrix<double, 7, 7> H;
  double r2 = 0.0;
  int m = 0;
  refiner.normalEquations(S, active, H, r2, m);
  const double variance_factor = m > 7 ? r2 / (m - 7) : 1.0;
  result.information = H / std::max(1.0, variance_factor);
  return result;
}

double loopDisagreementChi2(const Sim3d& S_w_current, const Sim3d& S_w_candidate,
                            const Sim3d& S_current_candidate,
                            const Eigen::Matrix<double, 7, 7>& information) {
  const Sim3d implied = S_w_current.inverse() * S_w_candidate;
  const Eigen::Matrix<double, 7, 1> d = (implied * S_current_candidate.inverse()).log();
  return d.dot(information * d);
}

}  // namespace ldsm::loop
