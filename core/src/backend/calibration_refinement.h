// Online refinement of the camera calibration, estimated from the window.
//
// The correction c = [k, s, dcx, dcy] of the configured (rectified) pinhole K0:
//   - k, a residual radial distortion: a ray with pinhole coordinates x = (X/Z, Y/Z) appears at
//     normalized coordinates x (1 + k |x|^2) (camera/radial_distortion.h);
//   - s, a common log scale of the focal lengths: fx = fx0 e^s, fy = fy0 e^s;
//   - (dcx, dcy), a shift of the principal point in full-resolution pixels.
// The window evaluates its residuals with the corrected camera (host pixel -> ray: K^-1, then
// removeRadial; projection -> target pixel: applyRadial, then K). After each window optimisation,
// calibrationEnvelopeStep() takes the Newton step in c of the window energy with every frame
// parameter and depth re-optimised (Schur complement of the whole Gauss-Newton system), so a
// direction the poses and depths can absorb - the radial flow of pure forward motion, a focal
// length under pure translation - carries little weight. CalibrationRefinement fuses those steps
// over keyframes and decides which correction the window applies.
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>
#include <Eigen/StdVector>

#include "camera/pyramid_camera.h"
#include "camera/radial_distortion.h"
#include "ldsm/config.h"

namespace ldsm {

/// The calibration parameters the window can refine, in the order of CalibVector.
enum CalibParam : int { kCalibRadial = 0, kCalibFocal = 1, kCalibCx = 2, kCalibCy = 3 };
constexpr int kCalibParams = 4;
using CalibVector = Eigen::Matrix<double, kCalibParams, 1>;
using CalibMatrix = Eigen::Matrix<double, kCalibParams, kCalibParams>;
/// Which parameters are refined (the others have no step and no weight).
using CalibMask = std::array<bool, kCalibParams>;

/// The indices of the parameters `mask` refines, in order.
std::vector<int> refinedParams(const CalibMask& mask);

/// The pinhole K0 with the focal scale and principal point shift of `c` applied (k is applied
/// separately, in normalized coordinates).
PinholeIntrinsics correctedIntrinsics(const PinholeIntrinsics& base, const CalibVector& c);

/// The calibration rows of the window's Gauss-Newton system, beside the frame block and depths.
/// The depth elimination of points that have no column in the window's coupling matrix (the
/// fixed points of reactivated map keyframes, whose depths the window solve does not move),
/// summed point by point: with a point's frame coupling c, depth curvature H_dd, gradient b_d
/// and calibration coupling H_dc, and d = 1 / H_dd (0 when H_dd <= 1e-10),
///   A = sum c c^T d, g = sum c b_d d, h = sum c H_dc^T d, hcc = sum H_dc H_dc^T d,
///   bc = sum H_dc b_d d.
struct EliminatedDepthTerms {
  Eigen::MatrixXd A;  ///< frames x frames
  Eigen::VectorXd g;
  Eigen::MatrixXd h;  ///< frames x 4
  CalibMatrix hcc = CalibMatrix::Zero();
  CalibVector bc = CalibVector::Zero();

  void reset(Eigen::Index frame_dim) {
    A.setZero(frame_dim, frame_dim);
    g.setZero(frame_dim);
    h.setZero(frame_dim, kCalibParams);
    hcc.setZero();
    bc.setZero();
  }
};

struct CalibrationTerms {
  Eigen::MatrixXd H_fc;  ///< sum w J_frames^T J_c (frames x 4)
  /// Per column of the coupling matrix (the points whose depths the solve moves).
  std::vector<CalibVector, Eigen::aligned_allocator<CalibVector>> H_dc;
  CalibMatrix H_cc = CalibMatrix::Zero();  ///< sum w J_c^T J_c
  CalibVector b_c = CalibVector::Zero();   ///< sum w J_c^T r
  /// The points without a column, eliminated as well.
  EliminatedDepthTerms other_depths;

  void reset(Eigen::Index frame_dim) {
    H_fc.setZero(frame_dim, kCalibParams);
    H_dc.clear();
    H_cc.setZero();
    b_c.setZero();
    other_depths.reset(frame_dim);
  }
};

/// The Newton step in the refined parameters of c and its curvature (information) with frames
/// and depths eliminated: with the full system [[H, C, h_fc], [C^T, D, h_dc], [., ., H_cc]] and
/// gradient [b, b_d, b_c],
///   curvature S = H_cc - h^T A^-1 h,  step = -S^-1 (b_c - h^T A^-1 g)
/// over the depth-reduced frame block A (every depth eliminated: the coupling matrix's columns
/// and terms.other_depths when it has the frames' size), restricted to the parameters of `mask`
/// (the others:
/// zero step, zero rows and columns). False (step and curvature 0) when S is not positive
/// definite or not finite. `schur_scratch` (optional) is the depth elimination's scratch
/// (subtractDepthSchur), kept by the caller between calls.
bool calibrationEnvelopeStep(const Eigen::MatrixXd& H, const Eigen::VectorXd& b,
                             const Eigen::Ref<const Eigen::MatrixXd>& coupling,
                             const std::vector<double>& H_dd, const std::vector<double>& b_d,
                             const CalibrationTerms& terms, const CalibMask& mask,
                             CalibVector* step, CalibMatrix* curvature,
                             Eigen::MatrixXd* schur_scratch = nullptr);

/// Fuses the windows' envelope steps into one estimate of c and keeps the correction the window
/// applies. Each window's measurement applied + step is weighted by its curvature matrix against
/// the older ones' (which keep `memory` of their weight per window). Each parameter's correction
/// switches on when its estimate leaves its dead band (in the first windows a wider one:
/// settle_windows) and stands `significance` realistic deviations from 0 (realisticSigma()), off
/// again below half of the band; while on it follows the estimate, clamped to its largest value.
class CalibrationRefinement {
 public:
  /// `window_keyframes`: keyframes per window (consecutive windows share all but one of them, so
  /// their information is not independent; significance test, CalibrationRefinementConfig).
  explicit CalibrationRefinement(const CalibrationRefinementConfig& config,
                                 int window_keyframes = 1);

  /// Starts from a correction made earlier (a loaded map's): estimate and applied correction are
  /// `c` for the focal and principal point parts (each on when not 0, refined or not, so that the
  /// camera is the one the map was measured in); the window estimates that follow refine it from
  /// there (the first with one window's weight, as from the configured camera).
  void startAt(double focal_log_scale, double cx_shift, double cy_shift);
  /// Adds one window's step, taken with applied() in effect.
  void addWindowStep(const CalibVector& step, const CalibMatrix& curvature);
  /// The correction the window applies (a parameter is 0 while off).
  const CalibVector& applied() const { return applied_; }
  /// The current estimate of c.
  const CalibVector& estimate() const { return estimate_; }
  /// 1-sigma uncertainty of each parameter of the estimate (0 before any window or when the
  /// parameter is not refined).
  CalibVector sigma() const;
  /// Realistic 1-sigma uncertainty of each parameter of the estimate: sigma() scaled by the
  /// windows' observed scatter (the mean squared innovation in units of the window's own formal
  /// deviation) and by the window overlap. 0 where sigma() is 0.
  CalibVector realisticSigma() const;
  bool engaged(int param) const { return engaged_[static_cast<size_t>(param)]; }
  /// Windows fused so far.
  int windows() const { return windows_; }
  /// Whether the camera is still being corrected: no window fused yet (nothing is known about the
  /// calibration), or over the last kQuietWindows windows an applied parameter moved by more than
  /// kMoveOfDeadBand of its dead band. Each window is one measurement of the calibration, and the
  /// frames tracked while it moves are the ones a correction bends; the keyframe rule takes
  /// keyframes more densely meanwhile (KeyframeConfig::settling_flow_scale).
  bool settling() const;
  static constexpr int kQuietWindows = 3;
  static constexpr double kMoveOfDeadBand = 0.5;
  /// The parameters refined.
  const CalibMask& mask() const { return mask_; }

 private:
  CalibrationRefinementConfig config_;
  CalibMask mask_{};
  std::vector<int> refined_;  ///< refinedParams(mask_)
  CalibVector dead_band_, max_, significance_;
  CalibVector estimate_ = CalibVector::Zero();
  CalibMatrix weight_ = CalibMatrix::Zero();  ///< fused information of the older windows
  CalibVector applied_ = CalibVector::Zero();
  std::array<bool, kCalibParams> engaged_{};
  double window_keyframes_ = 1.0;
  CalibVector scatter_ = CalibVector::Zero();  ///< fused mean squared normalised innovation
  double scatter_weight_ = 0.0;                ///< its fused weight (windows, with memory)
  int windows_ = 0;
  /// applied_ before window i + 1 was fused, at i % kQuietWindows (settling()).
  std::array<CalibVector, kQuietWindows> applied_before_{};
};

}  // namespace ldsm
