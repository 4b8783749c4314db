#include "loop/sim3_refinement.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include <ceres/ceres.h>

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
  double fx, fy, cx, cy, inv_sigma;

  template <typename T>
  bool operator()(const T* delta, T* r) const {
    const Eigen::Matrix<T, 3, 1> x = movedPoint(delta, p0);
    if (!(x.z() > T(1e-12))) return false;  // behind the camera: LM rejects this step
    r[0] = (T(fx) * x.x() / x.z() + T(cx) - T(pixel.x())) * T(inv_sigma);
    r[1] = (T(fy) * x.y() / x.z() + T(cy) - T(pixel.y())) * T(inv_sigma);
    return true;
  }
};

struct PointCost {
  Eigen::Vector3d p0;
  Eigen::Vector3d q;
  double scale;  // 1 / (|q| sigma_rel)

  template <typename T>
  bool operator()(const T* delta, T* r) const {
    const Eigen::Matrix<T, 3, 1> x = movedPoint(delta, p0);
    for (int i = 0; i < 3; ++i) r[i] = (x(i) - T(q(i))) * T(scale);
    return true;
  }
};

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

  Whitened evaluate(std::size_t i, const Sim3d& S) const {
    Whitened w;
    const Eigen::Vector3d x = S * c_[i].point_candidate;
    w.in_front = x.z() > 1e-12;
    if (w.in_front) {
      const Eigen::Vector2d u(cam_.fx * x.x() / x.z() + cam_.cx, cam_.fy * x.y() / x.z() + cam_.cy);
      w.pixel_error2 = (u - c_[i].pixel_current).squaredNorm();
      w.chi2_2d = w.pixel_error2 / (s_.pixel_sigma * s_.pixel_sigma);
    }
    if (hasCurrentDepth(c_[i])) {
      const double scale = 1.0 / (q_[i].norm() * s_.depth_relative_sigma);
      w.chi2_3d = ((x - q_[i]) * scale).squaredNorm();
    }
    return w;
  }

  bool isInlier(const Whitened& w) const {
    if (!w.in_front) return false;
    const bool ok2 = w.chi2_2d < s_.chi2_2d;
    if (w.chi2_3d < 0.0) return ok2;
    const bool ok3 = w.chi2_3d < s_.chi2_3d;
    return s_.reprojection_for_depth_matches ? (ok2 && ok3) : ok3;
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
      const Eigen::Vector3d p0 = S * c_[i].point_candidate;
      const bool depth = hasCurrentDepth(c_[i]);
      if (depth) {
        const ceres::AutoDiffCostFunction<PointCost, 3, 7> cost(
            new PointCost{p0, q_[i], 1.0 / (q_[i].norm() * s_.depth_relative_sigma)});
        add(cost, 3);
      }
      if (!depth || s_.reprojection_for_depth_matches) {
        const ceres::AutoDiffCostFunction<ReprojectionCost, 2, 7> cost(new ReprojectionCost{
            p0, c_[i].pixel_current, cam_.fx, cam_.fy, cam_.cx, cam_.cy, 1.0 / s_.pixel_sigma});
        add(cost, 2);
      }
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
      const Eigen::Vector3d p0 = S0 * c_[i].point_candidate;
      const bool depth = hasCurrentDepth(c_[i]);
      if (depth) {
        auto* cost = new ceres::AutoDiffCostFunction<PointCost, 3, 7>(
            new PointCost{p0, q_[i], 1.0 / (q_[i].norm() * s_.depth_relative_sigma)});
        problem.AddResidualBlock(cost, &loss_3d, delta);
      }
      if (!depth || s_.reprojection_for_depth_matches) {
        auto* cost = new ceres::AutoDiffCostFunction<ReprojectionCost, 2, 7>(new ReprojectionCost{
            p0, c_[i].pixel_current, cam_.fx, cam_.fy, cam_.cx, cam_.cy, 1.0 / s_.pixel_sigma});
        problem.AddResidualBlock(cost, &loss_2d, delta);
      }
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
