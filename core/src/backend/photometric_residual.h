// The photometric residual of one point in one target keyframe over the 8-pixel pattern
//   r_k = I_t[p'_k] - scale * I_h[p_k] - offset     (affineTransfer of host -> target)
// with Huber and gradient-dependent weights, and its linearisation. Geometric Jacobians are
// evaluated at the keyframes' first-estimate linearisation points (FEJ); residual values and image
// gradients at the current estimate. The pattern is evaluated as a struct of arrays by the SIMD
// kernels of kernels/ (pattern_sampling.h, pattern_accumulate.h); the (host, target) pair block
// is summed in SIMD lanes (PairAccumulator) and reduced once per pair and linearisation.
// With a radial correction k (calibration_refinement.h) the host pixel's ray is undistorted and
// the projection shifted by the distortion at the target's centre pixel (the pattern shares the
// shift); the linearisation can also yield the residual's terms in the calibration correction
// (k, focal scale, principal point) of the camera it is evaluated with.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "backend/active_point.h"
#include "backend/calibration_refinement.h"
#include "backend/window_keyframe.h"
#include "camera/pyramid_camera.h"
#include "image/compact_plane.h"
#include "image/gradient_pixel.h"
#include "kernels/pattern_accumulate.h"

namespace ldsm {

/// Relative parameters of a residual: [eps (6, left increment of T_t_h), a_h, b_h, a_t, b_t].
constexpr int kRelParams = 10;
using RelMatrix = Eigen::Matrix<double, kRelParams, kRelParams>;
using RelVector = Eigen::Matrix<double, kRelParams, 1>;

struct ResidualSettings {
  float huber_threshold = 9.f;                        ///< grey levels
  float gradient_weight_c = 50.f;                     ///< c of w = c^2 / (c^2 + |grad I|^2)
  float outlier_energy = 12.f * 12.f * kPatternSize;  ///< pattern energy above: outlier
  float border = 2.f;                                 ///< pixels kept free at the image border
};

/// Everything about a (host, target) keyframe pair that residuals share.
struct FramePairPrecalc {
  // Zero until set(): a pair never set (towards a keyframe without an image) reads as zeros, not
  // as uninitialised memory.
  Eigen::Matrix3f KRKi = Eigen::Matrix3f::Zero();  ///< K R_th K^-1 at the current estimate
  Eigen::Vector3f Kt = Eigen::Vector3f::Zero();    ///< K t_th at the current estimate
  Eigen::Matrix3f R0 = Eigen::Matrix3f::Zero();    ///< R_th at the linearisation point
  Eigen::Vector3f t0 = Eigen::Vector3f::Zero();    ///< t_th at the linearisation point
  float scale = 1.f, offset = 0.f, host_b = 0.f;
  LevelCamera cam;
  Level0View target_image;               ///< float, or 16-bit once the target is compacted
  simd::PatternSamplingParams sampling;  ///< the above as the sampling kernel takes them
  /// The larger of the two keyframes' adapted outlier thresholds (0: none adapted yet).
  float outlier_energy = 0.f;
  /// Residual radial distortion k of the images (calibration_refinement.h), 0: plain pinhole.
  float radial_k = 0.f;

  void set(const WindowKeyframe& host, const WindowKeyframe& target, const LevelCamera& camera);
};

/// The outlier threshold (pattern energy) of a residual of `pair`: the keyframes' adapted one,
/// or the fixed one of the settings before any adaptation.
inline float outlierEnergy(const FramePairPrecalc& pair, const ResidualSettings& settings) {
  return pair.outlier_energy > 0.f ? pair.outlier_energy : settings.outlier_energy;
}

/// DSO's adaptive outlier threshold (pattern energy) of a keyframe from the pattern energies of
/// the residuals aimed at it (outliers included; reordered): in RMS grey levels
///   th = (9.19 + 1.5 * rms_70) / 2,
/// with rms_70 the 70th percentile and 9.19 = 26 grey levels over the 8-pixel pattern. It follows
/// the residual level of the images (sharp or blurred, sensor noise, fast motion); a fixed
/// threshold rejects too much in blurred turns (kitti00_200 started 12 frames later lost its
/// heading in the turn: ATE 11.6 m fixed, 0.99 m adaptive). Returns 0 for fewer than 20 energies.
float adaptiveOutlierEnergy(std::vector<float>& pattern_energies);

/// The Gauss-Newton block of one (host, target) pair, summed over its residuals in SIMD lanes
/// and reduced once (reduce()) per linearisation.
class PairAccumulator {
 public:
  void reset() { sums_.reset(); }
  /// Residuals added since reset().
  int count() const { return sums_.count(); }
  /// H = sum w J_rel^T J_rel and b = sum w J_rel^T r over the residuals added since reset();
  /// `pair` is the precalc they were evaluated with.
  void reduce(const FramePairPrecalc& pair, RelMatrix& H, RelVector& b) const;
  simd::PatternPairSums& sums() { return sums_; }

 private:
  simd::PatternPairSums sums_;
};

/// One residual's terms of the calibration correction c (calibration_refinement.h): derivatives
/// in the radial k, the focal log scale and the principal point, at the pair's camera.
struct CalibrationResidualTerms {
  /// Input: the parameters wanted; the entries of the others are left untouched.
  CalibMask params{true, true, true, true};
  CalibMatrix H_cc = CalibMatrix::Zero();  ///< sum w J_c^T J_c
  CalibVector b_c = CalibVector::Zero();   ///< sum w J_c^T r
  CalibVector H_dc = CalibVector::Zero();  ///< sum w J_d J_c
  Eigen::Matrix<double, kRelParams, kCalibParams> coupling =
      Eigen::Matrix<double, kRelParams, kCalibParams>::Zero();  ///< sum w J_rel^T J_c
};

/// Receives the Gauss-Newton terms of one residual.
struct ResidualAccumulator {
  PairAccumulator* pair = nullptr;  ///< the (host, target) pair's block (unused if depth_only)
  double H_dd = 0.0;                ///< this residual's sum w J_d^2
  double b_d = 0.0;                 ///< sum w J_d r
  RelVector coupling = RelVector::Zero();  ///< sum w J_rel^T J_d
  bool depth_only = false;                 ///< accumulate H_dd and b_d only (pair may be null)
  /// When set (and not depth_only), receives the residual's calibration terms (overwritten, not
  /// added).
  CalibrationResidualTerms* calibration = nullptr;
  /// Only the calibration terms: nothing goes to the pair block or the point terms (pair may be
  /// null).
  bool calibration_only = false;
};

/// Evaluates the residual of `point` in the pair's target. Updates `res.state`, `res.energy`,
/// `res.projection` and returns the energy. When `acc` is given and the residual is an inlier,
/// adds its linearisation to it (pair block to acc->pair, point terms to acc's fields).
float evaluateResidual(const ActivePoint& point, PointResidual& res, const FramePairPrecalc& pair,
                       const ResidualSettings& settings, ResidualAccumulator* acc);
/// The same with the host ray's pinhole pixel given (hostRayPixel() of the pair's camera and
/// radial correction): the same for every pair of a window, so a point's residuals share it
/// instead of undistorting the host pixel once per residual (the same bits).
float evaluateResidual(const ActivePoint& point, const Eigen::Vector2f& host_ray_pixel,
                       PointResidual& res, const FramePairPrecalc& pair,
                       const ResidualSettings& settings, ResidualAccumulator* acc);

/// The pinhole pixel of the ray through image pixel (u, v) of `cam` with the radial correction
/// k (the pixel itself when k = 0).
Eigen::Vector2f hostRayPixel(const LevelCamera& cam, float k, float u, float v);

/// Gradient weight c^2 / (c^2 + |g|^2), square-rooted (the weight on the residual itself).
inline float gradientWeightSqrt(float dx, float dy, float c) {
  return std::sqrt(c * c / (c * c + dx * dx + dy * dy));
}

}  // namespace ldsm
