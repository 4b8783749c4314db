// Sliding-window photometric bundle adjustment: keyframe poses, affine brightness and the inverse
// depths of the active points, optimised jointly with Levenberg-Marquardt. Inverse depths are
// eliminated with the Schur complement (each depth couples only to its host and targets), so a
// step solves a dense (8 x keyframes)^2 system. Also marginalises keyframes and points into the
// MarginalizationPrior.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "backend/calibration_refinement.h"
#include "backend/kept_columns.h"
#include "backend/marginalization_prior.h"
#include "backend/photometric_residual.h"
#include "backend/window_keyframe.h"
#include "camera/pyramid_camera.h"
#include "concurrency/parallel_tasks.h"

namespace ldsm {

struct WindowOptimizerSettings {
  int max_iterations = 6;
  double initial_lambda = 1e-4;
  /// Stop when an accepted step lowers the energy by less than this fraction of the residuals'
  /// energy.
  double min_relative_decrease = 3e-4;
  /// A rejected step is retried with more damping only when it raised the energy by more than
  /// this fraction of the residuals' energy (an overshoot); otherwise the optimisation stops.
  double retry_increase = 1e-2;
  double affine_prior_a = 1e-3;  ///< prior weight on a (towards 0)
  double affine_prior_b = 1e-3;  ///< prior weight on b (towards 0)
  /// Weight anchoring the gauge keyframe (pose and affine brightness) to its first estimate.
  double gauge_anchor_weight = 1e8;
  /// Weight holding a reactivated map keyframe's pose and brightness at the map's estimate
  /// (per parameter): the gauge anchor's (fixed) unless set (> 0: free with that prior).
  double reactivated_weight = 0.0;
  /// After each optimisation, linearise the residuals in these calibration parameters as well
  /// and report the envelope step in them (calibration_refinement.h). None: no step.
  CalibMask estimate_calibration{};
  ResidualSettings residual;
};

struct WindowOptimizationResult {
  int iterations = 0;
  double initial_energy = 0.0;
  double final_energy = 0.0;
  int inlier_residuals = 0;
  int outlier_residuals = 0;
  double rmse = 0.0;  ///< sqrt(mean pattern-pixel energy) of inliers, grey levels
  /// With estimate_calibration: the Newton step in the calibration correction with frames and
  /// depths re-optimised, and its curvature, at the final state (calibrationEnvelopeStep());
  /// calibration_valid false when undefined.
  bool calibration_valid = false;
  CalibVector calibration_step = CalibVector::Zero();
  CalibMatrix calibration_curvature = CalibMatrix::Zero();
};

class WindowOptimizer {
 public:
  WindowOptimizer(const WindowOptimizerSettings& settings, const LevelCamera& camera)
      : settings_(settings), camera_(camera) {}

  /// From now on the residuals are linearised as parallel tasks on `tasks` (one per host
  /// keyframe; not owned; null: one after the other). The results are bit-identical either way.
  void setParallelTasks(concurrency::ParallelTasks* tasks) { tasks_ = tasks; }

  /// Optimises all keyframes of `window` (in window order) and their points.
  WindowOptimizationResult optimize(const std::vector<WindowKeyframe*>& window,
                                    const MarginalizationPrior& prior);

  /// Evaluates every residual at the current state (states and energies), no linearisation.
  double evaluate(const std::vector<WindowKeyframe*>& window, const MarginalizationPrior& prior);

  /// Moves the information of `points` (their inlier residuals, depths eliminated) into the
  /// prior.
  void marginalizePoints(const std::vector<WindowKeyframe*>& window,
                         const std::vector<const ActivePoint*>& points,
                         MarginalizationPrior& prior);

  /// Adds a keyframe's own priors (affine, gauge) to the prior, then marginalises it out.
  void marginalizeFrame(const std::vector<WindowKeyframe*>& window, const WindowKeyframe& frame,
                        MarginalizationPrior& prior);

  /// Gradient of the energy w.r.t. the keyframe parameters (8 per keyframe, window order) with
  /// the inverse depths held fixed, at the current state. For tests and diagnostics.
  Eigen::VectorXd frameGradient(const std::vector<WindowKeyframe*>& window,
                                const MarginalizationPrior& prior);

  /// dE/dc of the energy in the calibration correction (radial k, focal log scale, principal
  /// point; the parameters of settings().estimate_calibration, the others 0) at the current
  /// state and camera. For tests and diagnostics.
  CalibVector calibrationGradient(const std::vector<WindowKeyframe*>& window,
                                  const MarginalizationPrior& prior);

  /// The camera (level 0, focal length and principal point corrected) and radial distortion k
  /// (0: plain pinhole) the residuals are evaluated with.
  void setCamera(const LevelCamera& camera, double radial_k) {
    camera_ = camera;
    radial_k_ = radial_k;
  }
  double radialCorrection() const { return radial_k_; }
  /// Every (host h, target t) pair of `window` at index h * n + t, as the optimisation evaluates
  /// residuals: with camera() and radialCorrection() (the diagonal and pairs towards a keyframe
  /// without an image are left as they were). Numbers the keyframes (window_index).
  void framePairs(const std::vector<WindowKeyframe*>& window,
                  std::vector<FramePairPrecalc>& pairs) const;
  const LevelCamera& camera() const { return camera_; }
  /// The host ray's pinhole pixel of `p` with the window's camera and radial correction, as every
  /// pair of the window evaluates it (precalcPairs()).
  Eigen::Vector2f hostPixel(const ActivePoint& p) const {
    return hostRayPixel(camera_, static_cast<float>(radial_k_), p.u, p.v);
  }

  const WindowOptimizerSettings& settings() const { return settings_; }

 private:
  /// Per-parameter weights of a keyframe's anchor of weight `anchor` (pose, then a and b).
  static FrameVector anchorWeights(const WindowKeyframe& kf, double anchor);
  struct System {
    Eigen::MatrixXd H;  ///< frames (8n x 8n), residuals + priors
    Eigen::VectorXd b;
    /// 8n x columns: sum w J_frame^T J_d per point whose depth the solve moves (column[i] of
    /// point i; the fixed points of reactivated map keyframes have none: their depths take no
    /// step and no Schur term, and a window back on the map can hold more of them than of its
    /// own). The first columns of coupling_buffer, which keeps its memory from one
    /// linearisation to the next: the points change with every keyframe, and a matrix of their
    /// exact size (about 1 MB) was allocated each time.
    Eigen::MatrixXd::ColsBlockXpr coupling() { return coupling_buffer.leftCols(num_points); }
    Eigen::MatrixXd::ConstColsBlockXpr coupling() const {
      return coupling_buffer.leftCols(num_points);
    }
    /// A zero coupling of `rows` x `points` (keptColumns()).
    void resetCoupling(Eigen::Index rows, Eigen::Index points) {
      keptColumns(coupling_buffer, rows, points).setZero();
      num_points = points;
    }
    Eigen::MatrixXd coupling_buffer;
    Eigen::Index num_points = 0;  ///< columns of coupling()
    std::vector<double> H_dd;     ///< per point
    std::vector<double> b_d;      ///< per point
    std::vector<ActivePoint*> points;
    std::vector<Eigen::Index> column;  ///< per point: its coupling column, -1 for a fixed point
    double energy = 0.0;               ///< residuals and priors
    double photometric_energy = 0.0;   ///< the residuals' part of energy
    int inliers = 0, outliers = 0;
    double inlier_energy = 0.0;
    CalibrationTerms calibration;  ///< calibration terms (linearizeCalibration() only)
  };

  void precalcPairs(const std::vector<WindowKeyframe*>& window);
  /// Linearises every residual (and priors) at the current state into `sys`.
  void linearize(const std::vector<WindowKeyframe*>& window, const MarginalizationPrior& prior,
                 System& sys);
  /// The calibration terms of every residual at the state `sys` was linearised at
  /// (sys.calibration).
  void linearizeCalibration(const std::vector<WindowKeyframe*>& window, System& sys);
  /// Adds the keyframe priors (affine towards 0, gauge anchor) and the marginalisation prior.
  double addPriors(const std::vector<WindowKeyframe*>& window, const MarginalizationPrior& prior,
                   Eigen::MatrixXd* H, Eigen::VectorXd* b) const;
  /// Adds `sign` times the marginalisation prior at the window's current state to H and b (when
  /// given); returns `sign` times its energy.
  double addMarginalizationPrior(const std::vector<WindowKeyframe*>& window,
                                 const MarginalizationPrior& prior, double sign, Eigen::MatrixXd* H,
                                 Eigen::VectorXd* b) const;
  /// Solves the damped Schur-complemented system; returns frame and point steps.
  void solve(const System& sys, double lambda, Eigen::VectorXd& frame_step,
             std::vector<double>& point_step) const;

  /// What a linearisation changes of the points (besides the system): kept before a trial step
  /// and put back when the step is rejected, instead of linearising the kept state again.
  struct SavedPoint {
    float hessian_idepth, gradient_idepth;
    int inlier_residuals;
  };
  void saveResidualStates(const std::vector<ActivePoint*>& points);
  void restoreResidualStates(const std::vector<ActivePoint*>& points);

  WindowOptimizerSettings settings_;
  LevelCamera camera_;
  std::vector<SavedPoint> saved_points_;
  std::vector<PointResidual> saved_residuals_;
  std::vector<PointResidual> residual_scratch_;  ///< marginalizePoints: one point's residuals
  double radial_k_ = 0.0;
  using RelCalibMatrix = Eigen::Matrix<double, kRelParams, kCalibParams>;
  /// Per (host, target) pair: sum over its residuals of w J_rel^T J_c.
  std::vector<RelCalibMatrix, Eigen::aligned_allocator<RelCalibMatrix>> calibration_pair_;
  std::vector<FramePairPrecalc> pairs_;                ///< n x n, [host * n + target]
  std::vector<Eigen::Matrix<double, 6, 6>> adjoints_;  ///< Ad(T_th) at the linearisation points
  std::vector<PairAccumulator> pair_acc_;  ///< n x n, the pairs' blocks during a linearisation
  /// What a host's linearisation task keeps for the energy sums made afterwards in order.
  struct HostTerms {
    size_t first_point = 0;         ///< its first point's index in the system
    Eigen::Index first_column = 0;  ///< its first moving point's coupling column
    std::vector<float> energies;    ///< per residual: the energy it adds (outliers: the cap)
    std::vector<unsigned char> inlier;
    int outliers = 0;
  };
  std::vector<HostTerms> host_terms_;
  /// The solve's scaled coupling matrix (subtractDepthSchur), kept between solves: only its
  /// memory is reused, every solve writes all of it.
  mutable Eigen::MatrixXd schur_scratch_;
  /// The optimisation's current and trial systems, kept between keyframes for their memory.
  System sys_, trial_;
  concurrency::ParallelTasks* tasks_ = nullptr;
};

}  // namespace ldsm
