// A keyframe as it leaves the optimisation window, handed on as a value (to loop closure, and to
// whatever keeps the map): its final pose and brightness, the points it hosted with their final
// depths and pattern intensities, its corners with depths (for ORB descriptors and PnP), and its
// level-0 image for describing it. Nothing in it refers back into the window.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "ldsm/image.h"
#include "math/se3.h"
#include "model/affine_light.h"
#include "model/orb_descriptor.h"
#include "model/patch_point.h"

namespace ldsm {

/// A keyframe's pose relative to another keyframe of the window, as one state of the window
/// optimisation estimated it when the keyframe left (LDSM: the pose graph's relative-pose
/// constraints come from the local bundle adjustment, never from earlier pose-graph results).
struct KeyframeLink {
  int other = -1;
  SE3d T_this_other;      ///< maps points of `other`'s camera into this keyframe's camera
  int shared_points = 0;  ///< points hosted by either with an inlier residual in the other
  /// `other` is a map keyframe brought back into the window (reuse): fixed at its map pose.
  bool map_keyframe = false;
};

struct MarginalizedKeyframe {
  int id = -1;
  std::int64_t frame_index = 0;
  double timestamp = 0.0;
  double exposure = 1.0;  ///< exposure time (1 when unknown)
  AffineLight aff;
  SE3d T_w_c;                            ///< camera-to-world, the window's final estimate
  float radial_k = 0.f;                  ///< residual radial distortion the window applied
  std::vector<PatchPoint> points;        ///< hosted points with a converged depth
  std::vector<Eigen::Vector2f> corners;  ///< level-0 corner pixels (ORB is computed there)
  std::vector<float> corner_idepth;      ///< per corner, NaN: unknown
  /// ORB descriptors, one per corner once described (describing drops the corners too close to
  /// the border for a descriptor); empty before.
  std::vector<OrbDescriptor> descriptors;
  ImageF image;  ///< level-0 intensity (photometrically corrected); dropped once described
  /// Map points (reactivated keyframes) that were inliers in this keyframe when it was made.
  int map_points_in_view = 0;
  /// Distance the camera travelled (keyframe to keyframe, map units) up to this keyframe.
  double path_length = 0.0;
  /// The newest keyframe of the window when this one left it.
  int newest_when_left = -1;
  /// Redundant with the map (reuse): only its pose is kept.
  bool culled = false;
  /// Its relative poses to the other keyframes of the window (active and reactivated) when it
  /// left, with the points they shared.
  std::vector<KeyframeLink> links;
};

}  // namespace ldsm
