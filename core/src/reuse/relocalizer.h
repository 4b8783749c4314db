// Relocalisation after tracking was lost: finds the camera of a new frame in the existing map,
// so tracking resumes in the same map frame instead of a new, disconnected map.
//   1. corners of the frame (Shi-Tomasi) with ORB descriptors;
//   2. candidate map keyframes: those near the last known pose (spatial index), the covisible
//      neighbourhood of the keyframes last in the window, and those that look like the frame
//      anywhere in the map (a bag-of-words query, when given: a kidnapped camera, a loaded map);
//   3. ORB matches to each candidate's corners with depth, the best candidates by match count;
//   4. RANSAC PnP of the candidate's 3D corners against the frame's corners;
//   5. direct (photometric) alignment of the candidate's points to the frame from the PnP pose,
//      which must hold (enough inliers, correlated patterns) for the relocalisation to count;
//      where no PnP pose held, from the own pose of each candidate whose PnP failed
//      (reuse.relocalization_direct_start), with a stronger correlation.
// confirm() checks a pose found another way (the kept window's track) with step 5 alone;
// crossCheck() asks the other map keyframes around an answer before a new window is built on it.
// Runs on the tracking thread while tracking is lost; reads the map store.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "alignment/direct_alignment.h"
#include "alignment/pnp_ransac.h"
#include "camera/pyramid_camera.h"
#include "features/corner_detector.h"
#include "features/orb_extractor.h"
#include "ldsm/config.h"
#include "map/map_store.h"

namespace ldsm {

struct RelocalizationResult {
  bool success = false;
  std::string failure;   ///< why not (empty on success)
  int keyframe_id = -1;  ///< the map keyframe the frame was found against
  SE3d T_c_w;            ///< the frame's pose (world -> camera)
  AffineLight aff;       ///< the frame's affine brightness
  int matches = 0;       ///< ORB matches with depth to that keyframe
  int pnp_inliers = 0;
  int direct_inliers = 0;
  int direct_points = 0;
  /// The fit that found the frame started from the candidate keyframe's own pose (its PnP failed
  /// and no candidate's PnP pose held), not from a PnP pose; refineFromNearer() may have moved
  /// the result to a nearer keyframe since.
  bool from_keyframe_pose = false;
  /// The keyframe whose fit first found the frame, before refineFromNearer() moved the result to
  /// keyframe_id (equal when it did not): crossCheck() asks neither.
  int found_keyframe_id = -1;
};

class Relocalizer {
 public:
  Relocalizer(const ReuseConfig& config, const PyramidCamera& camera);

  /// Map keyframes that look like a view with these ORB descriptors (place recognition, e.g.
  /// the loop closer's bag of words), best first.
  using PlaceQuery = std::function<std::vector<int>(const std::vector<OrbDescriptor>&)>;

  /// Looks for `frame` (exposure time `exposure`) in `map`, near `last_T_c_w` (the last pose
  /// known), around `recent_ids` (the keyframes last in the window) and, given `places`, in the
  /// keyframes anywhere in the map that look like it. `median_depth` scales the spatial search.
  RelocalizationResult relocalize(const ImagePyramid& frame, double exposure, const MapStore& map,
                                  const SE3d& last_T_c_w, const std::vector<int>& recent_ids,
                                  double median_depth, const PlaceQuery& places = {});

  /// Checks a pose found another way (the kept window's track after a loss) against the map:
  /// direct alignment, from `T_c_w`, of the map keyframes nearest to it (within the search radius
  /// of `median_depth`, at most three, nearest first); the first that holds at a pose `agrees`
  /// accepts (any, when empty) gives the result (its keyframe and the pose it aligned to), none:
  /// failure with the reason. One keyframe's fit can end at a wrong minimum (a repeated texture:
  /// vamr_desk_loop's checkerboard, 3.1 degrees off with 79 % inliers), which the next one's does
  /// not share. No ORB, no PnP: the frame's corners may be too few to match (vamr_desk_loop after a
  /// gap: 17-22 matches, 4-7 PnP inliers) where the direct fit of the map's points still holds.
  RelocalizationResult confirm(const ImagePyramid& frame, double exposure, const MapStore& map,
                               const SE3d& T_c_w, double median_depth,
                               const std::function<bool(const SE3d&)>& agrees) const;

  /// What crossCheck() made of an answer.
  enum class CrossCheck {
    kConfirmed,  ///< more of the other map keyframes that align to the frame do so at the answer
    kUnchecked,  ///< no other map keyframe near it aligns to the frame: nothing speaks against it
    kRefused,    ///< at least one aligns elsewhere, and no fewer elsewhere than at the answer
  };
  /// Checks `answer` (a success of relocalize()) against the map keyframes nearest to its pose
  /// other than the one it was found in (and the one first found, before refineFromNearer):
  /// direct alignment of each (at most three, nearest first) from the answer's pose; those whose
  /// fit holds vote, at the answer (`agree` with its pose) or elsewhere. One keyframe's fit can
  /// hold at a wrong pose (a repeated texture, a far viewpoint), the answer's and a neighbour's
  /// alike. Where the neighbours agree among themselves elsewhere they are no surer: from a pose
  /// 0.2 median depths off on vamr_desk_loop's checkerboard they ended 0.02-0.08 median depths
  /// from it, and taking their pose made runs worse (docs/map-reuse.md, "Cross-checking the map's
  /// answer").
  CrossCheck crossCheck(const ImagePyramid& frame, double exposure, const MapStore& map,
                        double median_depth,
                        const std::function<bool(const SE3d&, const SE3d&)>& agree,
                        const RelocalizationResult& answer) const;

 private:
  /// 1. The frame's corners and ORB descriptors; false (and why) when too few.
  bool describeFrame(const ImagePyramid& frame, std::string& failure);
  /// 2. Map keyframes near the last pose and around the last window.
  std::vector<int> candidates(const MapStore& map, const SE3d& last_T_c_w,
                              const std::vector<int>& recent_ids, double median_depth) const;
  /// 3. (ORB matches with a depth, id) of each candidate, most matches first.
  std::vector<std::pair<int, int>> rankByMatches(const MapStore& map,
                                                 const std::vector<int>& ids) const;
  /// 4. PnP of the keyframe's corners against the frame's (fills out's match counts and, failed,
  /// its reason).
  PnpRansacResult solvePnp(const MarginalizedKeyframe& kf, const KeyframeRecord& pose,
                           RelocalizationResult& out) const;
  /// 5. Direct alignment of the keyframe's points from T_start; it must also correlate (more
  /// strongly `from_keyframe_pose`, T_start the keyframe's own pose: no PnP pose backs it).
  DirectAlignmentResult alignDirectly(const MarginalizedKeyframe& kf, const KeyframeRecord& pose,
                                      const ImagePyramid& frame, double exposure,
                                      const SE3d& T_start, bool from_keyframe_pose = false) const;
  /// Direct alignment of `kf` from T_start (alignDirectly); where it holds and is seen from a
  /// nearer viewpoint than `best` (its rotation from the keyframe, `best_angle`), it becomes
  /// `best` with `counts`' match counts; where it fails while nothing has held, `best` says why.
  void considerFit(const MarginalizedKeyframe& kf, const KeyframeRecord& pose,
                   const ImagePyramid& frame, double exposure, const SE3d& T_start,
                   bool from_keyframe_pose, const RelocalizationResult& counts,
                   RelocalizationResult& best, double& best_angle) const;
  /// 6. From the pose found, direct alignment to the map keyframes seen from nearer (within the
  /// search radius, or covisible with the one found): the nearest that holds gives the pose. A
  /// match found by place recognition may be a keyframe far from the frame, and the direct fit to
  /// a far view is the least accurate one (on vamr_desk_loop 1.6 cm off from 12 cm away).
  void refineFromNearer(const ImagePyramid& frame, double exposure, const MapStore& map,
                        double median_depth, RelocalizationResult& best) const;
  /// Direct alignment from `T_c_w` of the map keyframes with points among candidates() around
  /// that pose (with `skip_id`'s covisible neighbours, when >= 0), nearer than `max_distance` and
  /// other than `skip_id` and `also_skip_id`, at most three, nearest first: each fit that holds
  /// goes to `visit` as a result (keyframe, pose, brightness, direct counts; success set); true
  /// once `visit` returns true (the rest are not tried).
  bool forEachNearestFit(const ImagePyramid& frame, double exposure, const MapStore& map,
                         const SE3d& T_c_w, double median_depth, int skip_id, double max_distance,
                         const std::function<bool(const RelocalizationResult&)>& visit,
                         int also_skip_id = -1) const;
  /// forEachNearestFit from `T_c_w` (a copy: `out` may hold it); the first fit that holds (at a
  /// pose `accept` accepts, when given) sets `out`'s keyframe, pose, brightness and direct counts
  /// and returns true.
  bool alignNearest(const ImagePyramid& frame, double exposure, const MapStore& map, SE3d T_c_w,
                    double median_depth, int skip_id, double max_distance,
                    const std::function<bool(const SE3d&)>& accept,
                    RelocalizationResult& out) const;
  /// The frame's affine brightness from a direct fit to `kf`.
  static AffineLight frameBrightness(const DirectAlignmentResult& direct,
                                     const MarginalizedKeyframe& kf, double exposure);

  ReuseConfig config_;
  PyramidCamera camera_;
  /// Made at the first frame looked for (3.2 MB at 1232x368 that a run without a loss never needs).
  std::optional<CornerDetector> corners_;
  OrbExtractor orb_;
  std::vector<Corner> corner_scratch_;
  std::vector<Eigen::Vector2f> pixels_;
  std::vector<OrbDescriptor> descriptors_;
  std::vector<std::uint32_t> kept_;
  PnpRansacSettings pnp_;
  DirectAlignmentSettings direct_;
};

}  // namespace ldsm
