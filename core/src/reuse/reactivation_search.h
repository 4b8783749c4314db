// Which map keyframes to bring back into the window (DSM's local map covisibility window, with
// LDSM's changes): candidates come from the covisibility-graph neighbourhood of the window and
// from the keyframes near the current camera (a spatial index, never a scan of the whole map);
// recent keyframes (the odometry's own past) are not candidates. A candidate must
//   1. look the same way (optical axes within max_view_angle_deg),
//   2. see the current view (geometric check: enough of its points project into the newest
//      keyframe in front of the camera), and
//   3. match it (feature check: enough ORB matches between its corners and the newest keyframe's
//      whose 3D corner projects near the matched corner), which rejects false covisibility from
//      a drifted pose or a repeated structure, and
//   4. fit it (direct check, reuse.direct_check): its points, aligned to the newest keyframe's
//      image coarse to fine, are mostly inliers with patterns that correlate with the image, and
//      the aligned pose lies within the basin of the window's full-resolution optimisation.
// A candidate must also be a revisit, not the odometry's recent past: it left the window at least
// min_keyframe_age keyframes ago, and the camera came back to it (it travelled revisit_ratio
// times the straight-line distance since, or is practically where the candidate was). Moving
// forward, earlier keyframes still see the road or corridor ahead; bringing them back would only
// stretch the window over what the odometry measures anyway.
#pragma once

#include <string>
#include <vector>

#include "camera/pyramid_camera.h"
#include "ldsm/config.h"
#include "map/map_store.h"
#include "math/se3.h"
#include "model/affine_light.h"
#include "model/marginalized_keyframe.h"
#include "model/orb_descriptor.h"

namespace ldsm {

class ImagePyramid;  // (alignment/direct_alignment.h: the direct check's image)

/// The newest keyframe as the search sees it.
struct ReuseView {
  int keyframe_id = -1;
  SE3d T_c_w;  ///< world -> camera
  LevelCamera camera;
  float radial_k = 0.f;
  std::vector<Eigen::Vector2f> corners;  ///< with descriptors, one each
  std::vector<OrbDescriptor> descriptors;
  double median_depth = 1.0;  ///< of the window's points seen from it
  double path_length = 0.0;   ///< distance travelled up to it (map units)
  /// The first keyframe of the window's chain: keyframes with smaller ids were made before the
  /// window last started (before a relocalisation, or in a loaded map's session), so the
  /// distance travelled since them is unknown and any of them is a revisit.
  int chain_start_id = 0;
  std::vector<int> window_ids;  ///< the active keyframes (searched from, never candidates)
  /// For the direct check (null: no direct check): the newest keyframe's image pyramid, the
  /// camera of its levels, its exposure time and affine brightness.
  const ImagePyramid* pyramid = nullptr;
  const PyramidCamera* pyramid_camera = nullptr;
  double exposure = 1.0;
  AffineLight aff;
};

/// Where a candidate's check ended.
enum class ReuseStage { Revisit, Geometry, Features, Direct, Accepted };

/// The outcome of checking one candidate.
struct ReuseCheck {
  int id = -1;
  bool accepted = false;
  std::string reason;  ///< why it was rejected
  double overlap = 0.0;
  int in_view = 0;
  int matches = 0;  ///< consistent ORB matches
  ReuseStage stage = ReuseStage::Revisit;
  /// The direct check (when it ran): inlier share of the points in view, mean pattern
  /// correlation, mean shift of the points between the window's and the aligned pose (pixels).
  double direct_inliers = 0.0;
  double correlation = 0.0;
  double shift_px = 0.0;
  /// How far an alignment at full resolution alone, from the window's pose, ends from the
  /// coarse-to-fine one (pixels; 0 when the shift is within reuse.direct_basin_px anyway).
  double basin_miss_px = 0.0;
  /// Passed the feature check, but the direct check was not run (search() without it).
  bool direct_skipped = false;
  /// The direct check found the candidate where it fits (inliers and correlation passed) but
  /// beyond the window optimisation's basin: the window has drifted from the map. With
  /// T_view_kf_aligned, the candidate's pose relative to the view as the alignment found it
  /// (candidate camera -> view camera, in the view's map units).
  bool outside_basin = false;
  SE3d T_view_kf_aligned;
};

class ReactivationSearch {
 public:
  explicit ReactivationSearch(const ReuseConfig& config) : config_(config) {}

  /// Candidate ids (excluding `exclude` and recent keyframes), without checking them.
  std::vector<int> candidates(const ReuseView& view, const MapStore& map,
                              const std::vector<int>& exclude) const;
  /// Checks one map keyframe (its data and current pose record) against the view. With
  /// `direct` false a candidate that passes the feature check ends at ReuseStage::Direct with
  /// `direct_skipped` set, neither accepted nor rejected (its alignment is not run).
  ReuseCheck check(const ReuseView& view, const MarginalizedKeyframe& keyframe,
                   const KeyframeRecord& pose, bool direct = true) const;
  /// Completes a check that `check` (or `search`) left at the direct check (`direct_skipped`):
  /// what check() with `direct` would have done from there. Returns whether it is accepted.
  bool finishCheck(const ReuseView& view, const MarginalizedKeyframe& keyframe,
                   const KeyframeRecord& pose, ReuseCheck& c) const;
  /// The direct check of a candidate that passed the others (fills c's direct fields).
  bool checkDirect(const ReuseView& view, const MarginalizedKeyframe& keyframe,
                   const KeyframeRecord& pose, ReuseCheck& c) const;
  /// Candidates checked, the accepted ones first, best (most consistent matches) first.
  /// `direct` false: no direct check (the caller has no room for a map keyframe, or runs it with
  /// finishCheck() on the candidates in order until its window is full; the alignment costs a few
  /// milliseconds per candidate). The accepted ones are then met in the same order as they would
  /// be listed with `direct` (most matches first, ties in id order).
  std::vector<ReuseCheck> search(const ReuseView& view, const MapStore& map,
                                 const std::vector<int>& exclude, bool direct = true) const;

 private:
  ReuseConfig config_;
};

}  // namespace ldsm
