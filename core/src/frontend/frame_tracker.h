// The tracking module: tracks every frame against the newest keyframe (coarse tracker with motion
// hypotheses), keeps the motion history, and decides when a frame should become a keyframe
// (optical flow, brightness change and residual growth, as in DSO).
#pragma once

#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "camera/pyramid_camera.h"
#include "frontend/coarse_tracker.h"
#include "frontend/motion_hypotheses.h"
#include "ldsm/config.h"

namespace ldsm {

struct FrameTrackingOutcome {
  bool success = false;
  std::string failure;  ///< why tracking failed
  SE3d T_c_w;           ///< world -> camera of the frame
  AffineLight aff;
  double rmse = 0.0;             ///< level-0 RMSE, grey levels
  double inlier_fraction = 0.0;  ///< of the reference points in the image
  bool wants_keyframe = false;
  int hypotheses_tried = 0;
};

/// The tracker's settings: when to make a keyframe, and the coarse tracker's.
struct FrameTrackerSettings {
  KeyframeConfig keyframes;
  CoarseTrackerSettings coarse;
  double max_rmse_growth = 5.0;  ///< TrackingConfig::max_rmse_growth
};

class FrameTracker {
 public:
  FrameTracker(const FrameTrackerSettings& settings, const PyramidCamera& camera);

  /// A coarse tracker with this tracker's settings, for preparing references on another thread.
  std::unique_ptr<CoarseTracker> makeCoarseTracker() const;
  /// Tracks from now on with `prepared` (a coarse tracker whose reference was set elsewhere, the
  /// keyframe `id` at world -> camera pose T_ref_w); the previous one is handed back in
  /// `prepared` for reuse. While `calibration_settling`, the keyframe rule's flow weights are
  /// multiplied by KeyframeConfig::settling_flow_scale.
  void adoptReference(std::unique_ptr<CoarseTracker>& prepared, int id, const SE3d& T_ref_w,
                      bool calibration_settling);
  /// Starts a fresh motion history at a known pose, that of a frame taken at `timestamp` (seconds),
  /// with no velocity known.
  void resetMotion(const SE3d& T_c_w_last, const AffineLight& aff_last, double timestamp);
  /// The camera's motion over the last `seconds` before the last frame (prelast -> last, e.g. from
  /// the initialisation's reference to its last frame): the constant-velocity guess from now on.
  void setVelocity(const SE3d& T_last_prelast, double seconds);
  /// The last frame's pose was refined (it became a keyframe): keep the velocity, move the pose.
  void refineLastPose(const SE3d& T_c_w) { T_last_w_ = T_c_w; }
  bool hasReference() const { return has_reference_; }
  int referenceKeyframeId() const { return reference_id_; }
  const SE3d& referencePose() const { return T_ref_w_; }

  /// How far the motion guesses reach around the constant-velocity guess.
  enum class Search {
    kNoRotations,  ///< no extra rotated guesses (the start pose is known from elsewhere, e.g. a
                   ///< relocalisation)
    kRotations,    ///< rotated by up to 4 degrees (HypothesisSettings: every frame)
    kWide,         ///< rotated by up to 14 degrees: after a loss, the camera moved meanwhile
  };

  /// Tracks `frame`, taken at `timestamp` (seconds), against the reference from the motion
  /// guesses of `search`. The motion guesses continue the last motion for the time since the last
  /// tracked frame (continuedVelocity()).
  FrameTrackingOutcome track(const ImagePyramid& frame, double exposure, double timestamp,
                             Search search = Search::kRotations);

  /// Frames closer to even spacing than this (the time since the last frame over the time the
  /// velocity spans, within 1 +- this) take the last motion as it is: timestamps jitter, and the
  /// frames of a steady camera are evenly spaced.
  static constexpr double kEvenSpacingTolerance = 0.25;
  /// A frame this long after the last tracked one (`timestamp` - the last frame's time, more than
  /// kMaxVelocityScale times the time the velocity spans): the motion model has no guess for it
  /// (frames rejected or dropped in between). False without a velocity.
  bool beyondMotionModel(double timestamp) const {
    return has_velocity_ && velocity_dt_ > 0.0 &&
           timestamp - t_last_ > kMaxVelocityScale * velocity_dt_;
  }
  /// The last tracked frame's time (NaN before one).
  double lastTrackedTime() const { return t_last_; }

  /// The motion is continued for at most this many times the time it spans.
  static constexpr double kMaxVelocityScale = 10.0;
  /// How many times the velocity's time span passed from the last frame at `t_last` to a frame
  /// at `t`, the velocity spanning `velocity_dt` seconds: 1 when unknown (a time not finite, not
  /// increasing) or within the tolerance of even spacing, else the ratio, at most
  /// kMaxVelocityScale.
  static double velocityScale(double t, double t_last, double velocity_dt);
  /// The motion guesses' velocity for a frame at `t`: `T_last_prelast` (spanning `velocity_dt`)
  /// continued along its screw motion for velocityScale() times its span; exactly
  /// `T_last_prelast` for evenly spaced frames.
  static SE3d continuedVelocity(const SE3d& T_last_prelast, double t, double t_last,
                                double velocity_dt);

  /// The pixels of `level` where the reference's points of that level fall for a frame at
  /// world -> camera pose T_c_w (points behind the camera or outside the image left out).
  /// Replaces `out`; allocates only when it grows beyond its capacity.
  void projectReferencePoints(int level, const SE3d& T_c_w,
                              std::vector<Eigen::Vector2f>& out) const;

  /// The motion history, to track a frame again (against a newer reference) as if the first
  /// attempt had not happened.
  struct MotionState {
    SE3d T_last_w, T_last_prelast;
    bool has_velocity = false, has_last = false;
    AffineLight last_aff;
    double last_rmse = 0.0, first_rmse = -1.0;
    double t_last = std::numeric_limits<double>::quiet_NaN();       ///< the last frame's time
    double velocity_dt = std::numeric_limits<double>::quiet_NaN();  ///< time T_last_prelast spans
  };
  MotionState motionState() const {
    return {T_last_w_,  T_last_prelast_, has_velocity_, has_last_,   last_aff_,
            last_rmse_, first_rmse_,     t_last_,       velocity_dt_};
  }
  /// `m` with the translation of its last motion continued over the whole time from its last
  /// frame to `t` (no kMaxVelocityScale cap) and no rotation: the guess for a frame after a gap
  /// in which the camera kept moving (a robot driving on while its images were dark). The
  /// rotation is not continued: from one frame to the next it is mostly shake (the rendered
  /// corridor's 0.27 degrees per frame continued over 45 frames make 12 degrees where the camera
  /// turned 4.4); the wide search's rotated guesses around this one cover turns. `m` as it is
  /// without a velocity or a later `t`.
  static MotionState continuedOverGap(const MotionState& m, double t);
  void restoreMotion(const MotionState& m) {
    T_last_w_ = m.T_last_w;
    T_last_prelast_ = m.T_last_prelast;
    has_velocity_ = m.has_velocity;
    has_last_ = m.has_last;
    last_aff_ = m.last_aff;
    last_rmse_ = m.last_rmse;
    first_rmse_ = m.first_rmse;
    t_last_ = m.t_last;
    velocity_dt_ = m.velocity_dt;
  }

 private:
  bool keyframeWanted(const CoarseTrackingResult& r, double rmse) const;

  KeyframeConfig kf_config_;
  double flow_scale_ = 1.0;  ///< on the flow weights (adoptReference)
  double max_rmse_growth_ = 0.0;
  /// Outside the wide search, a frame is not the tracked scene also when its residual grows past
  /// this share of max_rmse_growth while fewer than this share of its points are inliers
  /// (FrameTracker::track).
  static constexpr double kOutlierGrowthShare = 0.6;
  static constexpr double kOutlierGrowthInliers = 0.75;
  PyramidCamera camera_;
  std::unique_ptr<CoarseTracker> tracker_;
  HypothesisSettings hypotheses_;
  HypothesisSettings hypotheses_without_rotations_;  ///< Search::kNoRotations
  HypothesisSettings hypotheses_wide_;               ///< Search::kWide
  bool has_reference_ = false;
  int reference_id_ = -1;
  SE3d T_ref_w_;
  SE3d T_last_w_;
  SE3d T_last_prelast_;
  bool has_velocity_ = false;
  bool has_last_ = false;
  AffineLight last_aff_;
  double last_rmse_ = 0.0;
  double first_rmse_ = -1.0;  ///< RMSE of the first frame tracked against the reference
  double t_last_ = std::numeric_limits<double>::quiet_NaN();
  double velocity_dt_ = std::numeric_limits<double>::quiet_NaN();
};

}  // namespace ldsm
