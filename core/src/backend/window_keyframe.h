// A keyframe while it is in the optimisation window: its image pyramid, its pose and affine
// brightness (current estimate and the first-estimate linearisation point), and the points it
// hosts.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "backend/active_point.h"
#include "backend/immature_point.h"
#include "image/image_pyramid.h"
#include "math/se3.h"
#include "model/affine_light.h"
#include "model/patch_point.h"

namespace ldsm {

/// Parameters of a keyframe in the optimiser: [xi (6, left increment of T_c_w), a, b].
constexpr int kFrameParams = 8;

/// A point candidate of a keyframe whose depth is still being searched for.
struct ImmatureCandidate {
  ImmaturePoint point;
  bool is_corner = false;
};
using FrameVector = Eigen::Matrix<double, kFrameParams, 1>;

class WindowKeyframe {
 public:
  WindowKeyframe(int id, std::int64_t frame_index, double timestamp, double exposure,
                 std::unique_ptr<ImagePyramid> pyramid)
      : id_(id),
        frame_index_(frame_index),
        timestamp_(timestamp),
        exposure_(exposure),
        pyramid_(std::move(pyramid)) {}

  int id() const { return id_; }
  std::int64_t frameIndex() const { return frame_index_; }
  double timestamp() const { return timestamp_; }
  double exposure() const { return exposure_; }
  const ImagePyramid& pyramid() const { return *pyramid_; }
  /// False for a reactivated map keyframe: it hosts points but is never a residual's target.
  bool hasImage() const { return pyramid_ != nullptr; }
  std::unique_ptr<ImagePyramid> releasePyramid() { return std::move(pyramid_); }
  /// Frees what the keyframe no longer needs once a newer keyframe exists (ImagePyramid::compact:
  /// all but the level-0 intensities, its residuals' target image; in 16 bits with
  /// `level0_16bit`).
  void compactPyramid(bool level0_16bit) {
    if (pyramid_) pyramid_->compact(level0_16bit);
  }
  /// Hands the level-0 image on as it leaves the window (ImagePyramid::takeIntensity0); nothing
  /// may sample the keyframe afterwards.
  void takeImage(ImageF& out) {
    if (pyramid_) pyramid_->takeIntensity0(out);
  }

  /// Sets the current estimate and makes it the linearisation point (first estimate).
  void setInitialState(const SE3d& pose_c_w, const AffineLight& affine) {
    T_c_w = T_c_w_eval = T_c_w_backup = pose_c_w;
    aff = aff_eval = aff_backup = affine;
  }
  /// Current state minus the linearisation point, in the optimiser's parametrisation.
  FrameVector delta() const {
    FrameVector d;
    d.head<6>() = (T_c_w * T_c_w_eval.inverse()).log();
    d[6] = aff.a - aff_eval.a;
    d[7] = aff.b - aff_eval.b;
    return d;
  }
  void backup() {
    T_c_w_backup = T_c_w;
    aff_backup = aff;
  }
  void restore() {
    T_c_w = T_c_w_backup;
    aff = aff_backup;
  }
  void applyStep(const FrameVector& step) {
    T_c_w = SE3d::exp(step.head<6>()) * T_c_w;
    aff.a += step[6];
    aff.b += step[7];
  }

  SE3d T_c_w;       ///< current estimate, world -> camera
  AffineLight aff;  ///< current affine brightness
  SE3d T_c_w_eval;  ///< first-estimate linearisation point of the geometric Jacobians
  AffineLight aff_eval;
  int window_index = -1;         ///< position in the window's Hessian (set by the window)
  bool is_gauge_anchor = false;  ///< the first keyframe: anchors the gauge (pose, affine a and b)
  /// A soft anchor of pose and affine brightness to the first estimate (weight per parameter;
  /// 0: none): a relocalised keyframe is held near where it was found, not fixed there.
  double anchor_weight = 0.0;
  /// The soft anchor's weight on the affine brightness (a, b), when > 0 (else anchor_weight): a
  /// relocalised keyframe holds the brightness gauge firmly (with the map keyframes gone from the
  /// window nothing else does) while its pose stays free to be corrected.
  double anchor_affine_weight = 0.0;
  /// A map keyframe brought back into the window (reuse): pose, brightness and its points' depths
  /// stay as the map has them; it has no image.
  bool is_reactivated = false;
  /// Map points (of reactivated keyframes) that were inliers in this keyframe when it was made.
  int map_points_in_view = 0;
  /// Distance the camera travelled (keyframe to keyframe, map units) up to this keyframe.
  double path_length = 0.0;
  std::vector<std::unique_ptr<ActivePoint>> points;
  std::vector<ImmatureCandidate> immature;
  /// Candidates selected where map points (reactivated keyframes) were seen: they wait, neither
  /// traced nor activated, while the map covers them, and become immature candidates when a map
  /// keyframe leaves the window (Mapper::wakeDormantPoints), so the window does not lose the
  /// points there together with the map keyframe.
  std::vector<ImmatureCandidate> dormant;
  int points_created = 0;  ///< active points ever hosted (for the marginalisation policy)
  /// Outlier threshold (pattern energy) of residuals hosted in or aimed at this keyframe, adapted
  /// to its residuals after its first optimisation; 0: the window's fixed threshold.
  float outlier_energy = 0.f;
  /// The corners selected in this keyframe (level-0 pixels; they carry ORB descriptors for loop
  /// closure) and the inverse depth each got as an active point (NaN: none).
  std::vector<Eigen::Vector2f> corners;
  std::vector<float> corner_idepth;
  /// Shi-Tomasi corners detected for loop closure and map reuse by the mapping stage (up to
  /// loop.corners_per_keyframe; empty when keyframes are not described). Those within 4 px of an
  /// odometry corner are skipped when the two lists are merged.
  std::vector<Eigen::Vector2f> loop_corners;
  /// Points this keyframe hosted that left the window with a converged depth (marginalised when
  /// the newest keyframe stopped seeing them): kept for the map once the keyframe leaves too.
  std::vector<PatchPoint> retired_points;

 private:
  SE3d T_c_w_backup;
  AffineLight aff_backup;
  int id_;
  std::int64_t frame_index_;
  double timestamp_;
  double exposure_;
  std::unique_ptr<ImagePyramid> pyramid_;
};

}  // namespace ldsm
