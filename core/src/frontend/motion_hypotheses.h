// Tracking a frame from several motion hypotheses (DSO's trackNewCoarse): the constant-velocity
// prediction first, then double, half and zero motion, the reference pose itself, then small
// rotations of the constant-velocity guess in 26 directions and a few angles. Each hypothesis is
// tracked coarse to fine with abort thresholds derived from the best result so far, so a poor one
// stops at the coarsest levels; the search ends as soon as a result's residual is below
// retrack_threshold times the last frame's. The rotated ones are screened at the coarsest level
// first, and only the best few are tracked to the finest (HypothesisSettings::screened_rotations).
#pragma once

#include <array>
#include <limits>

#include "frontend/coarse_tracker.h"
#include "image/image_pyramid.h"
#include "math/se3.h"
#include "model/affine_light.h"

namespace ldsm {

/// What is known about the motion before tracking a new frame.
struct MotionHistory {
  SE3d T_last_ref;      ///< pose of the last tracked frame relative to the reference (ref -> last)
  SE3d T_last_prelast;  ///< motion between the two last frames (prelast -> last)
  bool has_velocity = false;  ///< false: T_last_prelast is unknown (e.g. second frame)
  AffineLight last_affine;    ///< affine brightness of the last frame (initial guess)
  /// Level-0 RMSE of the last frame; infinity when unknown (then the first success is kept).
  double last_rmse = std::numeric_limits<double>::infinity();
};

enum class MotionHypothesisKind {
  kConstantVelocity,
  kDoubleMotion,
  kHalfMotion,
  kZeroMotion,     ///< the last frame's pose
  kReferencePose,  ///< identity: the frame sits at the reference
  kRotated,        ///< constant velocity and a small extra rotation
};

const char* toString(MotionHypothesisKind kind);

constexpr int kMaxHypothesisAngles = 4;
constexpr int kRotationDirections = 26;  ///< the faces, edges and corners of a cube

struct HypothesisSettings {
  /// Stop when a result's level-0 RMSE is below this times the last frame's; also the factor of
  /// the per-level abort thresholds over the best result so far.
  double retrack_threshold = 1.5;
  /// Extra rotation angles (radians) tried in each of the 26 directions; the first
  /// `rotation_angle_count` are used.
  std::array<double, kMaxHypothesisAngles> rotation_angles{{0.02, 0.04, 0.07, 0.0}};
  int rotation_angle_count = 3;
  /// The rotated hypotheses are first tracked at the coarsest level only, and this many of the
  /// best of them are then tracked down to level 0 (0: every one is tracked in full, as DSO does).
  /// Screening bounds the time of a hard frame (78 rotated hypotheses) to about that of twenty
  /// ordinary ones. The coarsest level ranks poorly (on the desk played back and forth, the
  /// reversal of the motion picked a wrong rotation with the best 3, ATE 0.0064 m over two passes
  /// against 0.0010 m with the best 10 or with every one in full).
  int screened_rotations = 10;
};

/// The search after a loss or a gap in time (FrameTracker::Search::kWide): the camera moved while
/// no frame was tracked, so the rotated guesses reach 2.3, 4.6, 9.2 and 13.8 degrees instead of
/// 1.1, 2.3 and 4 (104 guesses screened at the coarsest level, the best 10 tracked in full).
HypothesisSettings wideHypothesisSettings();

/// Number of hypotheses generated (5 + 26 * rotation_angle_count).
int motionHypothesisCount(const HypothesisSettings& settings);

/// Hypothesis `index` (0 <= index < motionHypothesisCount()) for T_frame_ref, and its kind.
SE3d motionHypothesis(int index, const MotionHistory& history, const HypothesisSettings& settings,
                      MotionHypothesisKind* kind);

struct HypothesisTrackingResult {
  bool success = false;
  int hypothesis = -1;  ///< index of the winning hypothesis, -1 when none succeeded
  MotionHypothesisKind kind = MotionHypothesisKind::kConstantVelocity;
  int tried = 0;     ///< hypotheses tracked (to level 0, or until a level aborted them)
  int screened = 0;  ///< rotated hypotheses tracked at the coarsest level only
  /// Level-0 RMSE of the winner, for failure detection (infinity when none succeeded).
  double rmse = std::numeric_limits<double>::infinity();
  SE3d T_frame_ref;    ///< winner's pose (the constant-velocity guess when none succeeded)
  AffineLight affine;  ///< winner's affine brightness
  CoarseTrackingResult tracking;  ///< winner's tracking details
};

/// Tracks `frame` against the tracker's reference from the hypotheses in order, keeping the best
/// successful one (lowest level-0 RMSE). Allocates nothing.
HypothesisTrackingResult trackWithHypotheses(CoarseTracker& tracker, const ImagePyramid& frame,
                                             double exposure, const MotionHistory& history,
                                             const HypothesisSettings& settings);

}  // namespace ldsm
