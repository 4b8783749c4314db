// Immature points (DSO): candidate points of a keyframe whose inverse depth is still an interval.
// Each new frame narrows the interval by an epipolar search: the interval's projection into the
// frame is walked in 1-pixel steps comparing the 8-pixel pattern, the best match is refined to
// sub-pixel by Gauss-Newton along the line, and the new interval is the best match +- an error
// bound that depends on how well the image gradient constrains a position along the line.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <limits>

#include "camera/pyramid_camera.h"
#include "image/gradient_pixel.h"
#include "ldsm/image.h"
#include "math/se3.h"
#include "model/residual_pattern.h"

namespace ldsm {

enum class TraceStatus : std::uint8_t {
  kUntraced,  ///< not traced yet
  kGood,      ///< matched; the interval was updated
  kOob,       ///< the interval projects outside the image (or behind the camera): drop it
  kOutlier,   ///< the best match's energy is too high (occlusion, wrong brightness, ...)
  /// The interval projects to < min_search_length pixels (no parallax), or to no more than a
  /// search could reach (2 (matching_error + epipolar_error) min_improvement): converged.
  kSkipped,
  kBadCondition,  ///< the gradient is (nearly) perpendicular to the line: search would not help
};

/// Name of a status ("GOOD", "OOB", ...), for logs.
const char* traceStatusName(TraceStatus status);

struct TraceSettings {
  float huber_threshold = 9.f;  ///< Huber threshold of a pattern residual, grey levels
  /// Best-match energy above kPatternSize * outlier_threshold^2 is an outlier (grey levels).
  float outlier_threshold = 12.f;
  float max_search_length = 100.f;  ///< longest walked segment, pixels (<= kMaxSearchLength)
  float min_search_length = 1.5f;   ///< shorter projected intervals are SKIPPED, pixels
  int second_best_radius = 2;       ///< steps around the best excluded from the second best
  int refine_iterations = 3;        ///< 1-D Gauss-Newton steps along the line
  /// Error bound e = matching_error + epipolar_error / cos(angle(gradient, line)), pixels: the
  /// sub-pixel matching accuracy, plus an error of the line's position (pose, calibration) which
  /// moves the match along the line by 1 / cos of that angle.
  float matching_error = 0.2f;
  float epipolar_error = 0.3f;
  /// BADCONDITION when the new interval (2 e) would not be at least this factor shorter than the
  /// projected one (or than max_search_length when that is shorter).
  float min_improvement = 2.f;
  /// Map the pattern through the rotation-only homography (else it keeps its host orientation).
  bool rotate_pattern = true;
};

class ImmaturePoint {
 public:
  /// Longest supported search segment, pixels.
  static constexpr int kMaxSearchLength = 256;
  /// c of the gradient weight w = c^2 / (c^2 + |grad I|^2), grey levels per pixel. A pixel with
  /// gradient g misplaced by delta pixels has a residual ~ |g| delta; the weight bounds its
  /// weighted square by ~ c^2 delta^2 for |g| >> c, so strong edges, whose residuals are dominated
  /// by sub-pixel misalignment, do not outvote the rest of the pattern. 50 is the value given
  /// with DSO's model (grey levels on a 0..255 scale).
  static constexpr float kDefaultGradientWeightC = 50.f;

  /// Creates the point at level-0 position (u, v) of the host keyframe, reading its pattern
  /// intensities and gradients (bilinear when (u, v) is not integer). Throws InputError when the
  /// pattern does not fit inside the image, the image has non-finite values there, or the prior
  /// interval is not 0 <= idepth_min <= idepth_max (idepth_max may be +inf).
  ImmaturePoint(ImageView<const GradientPixel> host, float u, float v, float idepth_min = 0.f,
                float idepth_max = std::numeric_limits<float>::infinity(),
                float gradient_weight_c = kDefaultGradientWeightC);

  /// Epipolar search in `target` (level 0 of the target frame, same camera as the host) and
  /// interval update. T_target_host maps host points into the target; affine = (scale, offset)
  /// with I_target ~ scale * I_host + offset. Returns (and stores) the status.
  TraceStatus trace(ImageView<const GradientPixel> target, const LevelCamera& camera,
                    const SE3f& T_target_host, const Eigen::Vector2f& affine,
                    const TraceSettings& settings);

  float u() const { return u_; }
  float v() const { return v_; }
  float idepthMin() const { return idepth_min_; }
  float idepthMax() const { return idepth_max_; }
  /// Middle of the interval; idepthMin() when the interval is unbounded.
  float idepthEstimate() const;
  /// Half width of the interval (+inf when unbounded).
  float idepthUncertainty() const { return 0.5f * (idepth_max_ - idepth_min_); }
  /// Energy of the best other local minimum (outside second_best_radius) / best energy, from the
  /// last search that had one (0 before any).
  float quality() const { return quality_; }
  TraceStatus lastStatus() const { return status_; }
  /// Length in pixels of the interval's projection in the last traced frame.
  float lastPixelInterval() const { return last_pixel_interval_; }
  /// Best match (sub-pixel) in the last frame with status GOOD or OUTLIER.
  const Eigen::Vector2f& lastMatch() const { return last_match_; }
  /// Pattern energy of that match.
  float lastEnergy() const { return last_energy_; }
  int outlierCount() const { return outlier_count_; }
  const std::array<float, kPatternSize>& colors() const { return colors_; }
  const std::array<float, kPatternSize>& weights() const { return weights_; }

  /// Ready for activation: bounded interval with (max - min) <= max_relative_width * estimate,
  /// quality >= min_quality, and the last trace neither OOB nor OUTLIER.
  bool isConverged(float max_relative_width, float min_quality) const;

 private:
  float u_, v_;
  std::array<float, kPatternSize> colors_{};
  std::array<float, kPatternSize> weights_{};
  float grad_xx_ = 0.f, grad_xy_ = 0.f, grad_yy_ = 0.f;  ///< pattern gradient structure tensor
  float idepth_min_;
  float idepth_max_;
  float quality_ = 0.f;
  float last_pixel_interval_ = std::numeric_limits<float>::infinity();
  float last_energy_ = 0.f;
  Eigen::Vector2f last_match_{-1.f, -1.f};
  int outlier_count_ = 0;
  TraceStatus status_ = TraceStatus::kUntraced;
};

}  // namespace ldsm
