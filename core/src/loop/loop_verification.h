// Geometric verification of a loop candidate and estimation of its Sim(3) constraint:
//   1. ORB matches current -> candidate (descriptor_matcher.h),
//   2. RANSAC PnP of the candidate's 3D points (features with inverse depth) against the current
//      keyframe's pixels (pnp_ransac.h); the relative scale from PnP solved both ways (LDSM: the
//      ratio of the two translations' lengths) when the cameras are far enough apart, else from
//      the median depth ratio of the PnP inliers that have depth in the current keyframe,
//   3. Sim(3) refinement with Huber norms, 3D-3D for matches with current depth, 2D otherwise
//      (sim3_refinement.h),
//   4. acceptance on the inlier counts after refinement.
// A candidate that fails from its PnP on gets a second chance, a guided search: its PnP's pose
// (with too few inliers, or one the later tests rejected; at least `guided_min_inliers`) predicts
// where each unmatched candidate point appears in the current keyframe, the unmatched current
// features within `guided_radius_px` of it are compared (the matching's Hamming limit and ratio
// test; each current feature to the candidate point it matches best), and stages 2-4 run again
// on the global and guided matches with the same thresholds. The global matching loses
// correspondences whose descriptor has a close rival anywhere in the image (repeating texture);
// near the predicted pixel the rival is not there.
// Convention: S_current_candidate maps a point from the candidate keyframe's camera frame, in the
// candidate's map scale, into the current keyframe's camera frame, in the current map scale:
//   q_current = S_current_candidate * p_candidate.
// With world-from-camera Sim(3) poses it is the loop edge measurement S_w_cur^-1 * S_w_cand.
#pragma once

#include <string>
#include <vector>

#include "alignment/pnp_ransac.h"
#include "loop/descriptor_matcher.h"
#include "loop/loop_types.h"
#include "loop/sim3_refinement.h"

namespace ldsm::loop {

/// Thresholds of verifyLoop(). Every failed test gives a rejection with a reason.
struct LoopVerificationSettings {
  DescriptorMatchSettings matching;
  int min_matches = 30;             ///< ORB matches
  int min_matches_with_depth = 20;  ///< of which the candidate feature has an inverse depth
  PnpRansacSettings pnp;            ///< pnp.min_inliers: RANSAC inliers needed
  Sim3RefinementSettings refinement;
  int min_inliers = 20;     ///< inliers after refinement (with and without depth)
  int min_inliers_3d = 10;  ///< inliers with depth in the current keyframe (fix scale)
  double min_scale = 0.05;  ///< plausible range of the relative scale
  double max_scale = 20.0;
  /// Guided search: the failed PnP's pose needs this many inliers (0: no guided search).
  int guided_min_inliers = 12;
  /// Guided search: a current feature is compared when it lies this close to the predicted pixel.
  double guided_radius_px = 8.0;
};

/// Outcome of verifyLoop().
struct LoopVerification {
  bool accepted = false;
  std::string reason;  ///< why it was rejected ("accepted" otherwise)
  int current_id = -1;
  int candidate_id = -1;
  int num_matches = 0;  ///< the global matches and the guided ones
  int num_guided_matches = 0;
  int num_matches_with_depth = 0;
  int num_pnp_inliers = 0;
  int num_inliers = 0;     ///< after refinement
  int num_inliers_3d = 0;  ///< of which with depth in the current keyframe
  double rms_reprojection_px = 0.0;
  double initial_scale = 0.0;         ///< the refinement's starting scale
  bool scale_from_both_ways = false;  ///< it came from PnP solved both ways (else depth ratios)
  Sim3d S_current_candidate;          ///< see the file comment; identity when rejected before PnP
  /// Information of S_current_candidate for a left perturbation exp(d) * S (Sim3RefinementResult).
  Eigen::Matrix<double, 7, 7> information = Eigen::Matrix<double, 7, 7>::Zero();
  std::vector<DescriptorMatch> inlier_matches;  ///< query = current, train = candidate
  double time_ms = 0.0;
};

/// Verifies that `candidate` shows the same place as `current` and estimates
/// S_current_candidate. Needs no pose prior: the odometry poses of a loop are drifted anyway.
/// Throws InputError for inconsistent keyframe features (sizes, indices), invalid intrinsics or
/// guided-search settings out of range.
LoopVerification verifyLoop(const KeyframeFeatures& current, const KeyframeFeatures& candidate,
                            const LoopVerificationSettings& settings);

}  // namespace ldsm::loop
