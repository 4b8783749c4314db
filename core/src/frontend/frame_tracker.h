// The tracking module: tracks every frame against the newest keyframe (coarse tracker with motion
// hypotheses), keeps the motion history, and decides when a frame should become a keyframe
// (optical flow, brightness change and residual growth, as in DSO).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "camera/pyramid_camera.h"
#include "frontend/coarse_tracker.h"
#include "frontend/motion_hypotheses.h"
#include "ldsm/config.h"
#include "model/depth_point.h"
#include "model/tracking_reference.h"

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

  /// Tracks from now on against `reference`, whose pyramid must stay alive, with the window's
  /// points projected into it.
  void setReference(const TrackingReference& reference, const std::vector<DepthPoint>& points);
  /// A coarse tracker with this tracker's settings, for preparing references on another thread.
  std::unique_ptr<CoarseTracker> makeCoarseTracker() const;
  /// Tracks from now on with `prepared` (a coarse tracker whose reference was set elsewhere, the
  /// keyframe `id` at world -> camera pose T_ref_w); the previous one is handed back in
  /// `prepared` for reuse. While `calibration_settling`, the keyframe rule's flow weights are
  /// multiplied by KeyframeConfig::settling_flow_scale.
  void adoptReference(std::unique_ptr<CoarseTracker>& prepared, int id, const SE3d& T_ref_w,
                      bool calibration_settling);
  /// Starts a fresh motion history at a known pose (after initialisation).
  void resetMotion(const SE3d& T_c_w_last, const AffineLight& aff_last);
  /// The last frame's pose was refined (it became a keyframe): keep the velocity, move the pose.
  void refineLastPose(const SE3d& T_c_w) { T_last_w_ = T_c_w; }
  bool hasReference() const { return has_reference_; }
  int referenceKeyframeId() const { return reference_id_; }
  const SE3d& referencePose() const { return T_ref_w_; }

  /// Tracks `frame` against the reference from the motion guesses; `rotations` false leaves out
  /// the extra rotated guesses (the start pose is known from elsewhere, e.g. a relocalisation).
  FrameTrackingOutcome track(const ImagePyramid& frame, double exposure, bool rotations = true);

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
  };
  MotionState motionState() const {
    return {T_last_w_, T_last_prelast_, has_velocity_, has_last_,
            last_aff_, last_rmse_,      first_rmse_};
  }
  void restoreMotion(const MotionState& m) {
    T_last_w_ = m.T_last_w;
    T_last_prelast_ = m.T_last_prelast;
    has_velocity_ = m.has_velocity;
    has_last_ = m.has_last;
    last_aff_ = m.last_aff;
    last_rmse_ = m.last_rmse;
    first_rmse_ = m.first_rmse;
  }

 private:
  bool keyframeWanted(const CoarseTrackingResult& r, double rmse) const;

  KeyframeConfig kf_config_;
  double flow_scale_ = 1.0;  ///< on the flow weights (adoptReference)
  double max_rmse_growth_ = 0.0;
  PyramidCamera camera_;
  std::unique_ptr<CoarseTracker> tracker_;
  HypothesisSettings hypotheses_;
  HypothesisSettings hypotheses_without_rotations_;  ///< track(..., rotations = false)
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
};

}  // namespace ldsm
