// The tracking module: tracks every frame against the newest keyframe (coarse tracker with motion
// hypotheses), keeps the motion history, and decides when a frame should become a keyframe
// (optical flow, brightness change and residual growth, as in DSO).
#pragma once

#include <string>
#include <vector>

#include "frontend/coarse_tracker.h"
#include "frontend/motion_hypotheses.h"
#include "frontend/pyramid_camera.h"
#include "ldsm/config.h"
#include "map/window_keyframe.h"

namespace ldsm {

struct FrameTrackingOutcome {
  bool success = false;
  std::string failure;  ///< why tracking failed
  SE3d T_c_w;           ///< world -> camera of the frame
  AffineLight aff;
  double rmse = 0.0;  ///< level-0 RMSE, grey levels
  bool wants_keyframe = false;
  int hypotheses_tried = 0;
};

class FrameTracker {
 public:
  FrameTracker(const Config& config, const PyramidCamera& camera, bool exposures_known);

  /// Tracks from now on against `keyframe`, whose pyramid must stay alive, with the window's
  /// points projected into it.
  void setReference(const WindowKeyframe& keyframe, const std::vector<DepthPoint>& points);
  /// Starts a fresh motion history at a known pose (after initialisation).
  void resetMotion(const SE3d& T_c_w_last, const AffineLight& aff_last);
  /// The last frame's pose was refined (it became a keyframe): keep the velocity, move the pose.
  void refineLastPose(const SE3d& T_c_w) { T_last_w_ = T_c_w; }
  bool hasReference() const { return reference_ != nullptr; }
  int referenceKeyframeId() const { return reference_id_; }
  const SE3d& referencePose() const { return T_ref_w_; }

  FrameTrackingOutcome track(const ImagePyramid& frame, double exposure);

 private:
  bool keyframeWanted(const CoarseTrackingResult& r, double rmse) const;

  KeyframeConfig kf_config_;
  PyramidCamera camera_;
  CoarseTracker tracker_;
  HypothesisSettings hypotheses_;
  const WindowKeyframe* reference_ = nullptr;
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
