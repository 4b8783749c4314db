// The reactivation search's direct check: a map keyframe's points, aligned to the newest
// keyframe's image, must fit it and lie within the basin of the window's full-resolution
// optimisation. Rendered planes with exact depths.
#include <gtest/gtest.h>

#include <random>

#include "image/image_pyramid.h"
#include "plane_scene.h"
#include "plane_scene_points.h"
#include "reuse/reactivation_search.h"

namespace ldsm {
namespace {

constexpr int kW = 320, kH = 240;
constexpr double kF = 260.0, kCx = 159.5, kCy = 119.5;

using test::isometry;
using test::tangentPose;

/// A map keyframe (id 5) at the origin with its points, and the newest keyframe's image seen
/// from T_w_view (truth); the view's pose estimate is set by each test.
struct DirectRevisit {
  test::PlaneScene scene = test::PlaneScene::wallAndFloor(4.0);
  PyramidCamera camera{PinholeIntrinsics{kF, kF, kCx, kCy, kW, kH}, 3};
  ImagePyramid target{kW, kH, 3, false};
  MarginalizedKeyframe kf;
  KeyframeRecord record{5, 50, 5.0, SE3d()};
  ReuseView view;
  SE3d T_w_view;

  explicit DirectRevisit(const SE3d& T_w_true) : T_w_view(T_w_true) {
    ImageF idepth;
    const ImageF host =
        scene.render(Eigen::Isometry3d::Identity(), kF, kF, kCx, kCy, kW, kH, &idepth);
    target.build(scene.render(isometry(T_w_true), kF, kF, kCx, kCy, kW, kH).view());
    kf.id = 5;
    kf.points = test::gridPatchPoints(host, idepth, 6, 8);
    view.keyframe_id = 80;
    view.camera = camera[0];
    view.pyramid = &target;
    view.pyramid_camera = &camera;
    view.T_c_w = T_w_true.inverse();
  }
  ReuseCheck check(const ReuseConfig& config = {}) const {
    ReuseCheck c;
    ReactivationSearch(config).checkDirect(view, kf, record, c);
    return c;
  }
  bool passes(const ReuseConfig& config = {}) const {
    ReuseCheck c;
    return ReactivationSearch(config).checkDirect(view, kf, record, c);
  }
};

TEST(ReactivationDirectCheck, AcceptsAMapKeyframeThatFitsWhereTheWindowPutsIt) {
  DirectRevisit r(tangentPose(0.02, -0.04, 0.05, 0.2, -0.05, 0.25));
  ASSERT_GT(r.kf.points.size(), 500u);
  const ReuseCheck c = r.check();
  EXPECT_TRUE(r.passes()) << c.reason;
  EXPECT_GT(c.direct_inliers, 0.95);
  EXPECT_GT(c.correlation, 0.9);
  EXPECT_LT(c.shift_px, 0.3);
}

TEST(ReactivationDirectCheck, TakesAnOffsetTheFullResolutionFitReachesAndNoFurther) {
  // The window's estimate of the view is off (a drift the map keyframe will correct): by 3 cm and
  // 0.6 degrees (5 px) the full-resolution fit, as the window optimisation, still reaches the
  // coarse-to-fine pose on this smooth texture; by 12 cm and 2.3 degrees (20 px) it does not.
  DirectRevisit r(tangentPose(0.02, -0.04, 0.05, 0.2, -0.05, 0.25));
  r.view.T_c_w = (r.T_w_view * tangentPose(0.0, 0.01, 0.0, 0.03, 0.0, 0.0)).inverse();
  const ReuseCheck near = r.check();
  EXPECT_TRUE(r.passes()) << near.reason;
  EXPECT_GT(near.shift_px, 4.0);
  EXPECT_LT(near.shift_px, 6.0);
  EXPECT_LT(near.basin_miss_px, 0.5);
  // A bound on the distance itself takes it out.
  ReuseConfig bounded;
  bounded.direct_max_shift_px = 2.0;
  EXPECT_FALSE(r.passes(bounded));
  r.view.T_c_w = (r.T_w_view * tangentPose(0.0, 0.04, 0.0, 0.12, 0.0, 0.0)).inverse();
  const ReuseCheck far = r.check();
  EXPECT_FALSE(r.passes());
  EXPECT_GT(far.direct_inliers, 0.95) << "it aligns coarse to fine: " << far.reason;
  EXPECT_GT(far.correlation, 0.9);
  EXPECT_GT(far.shift_px, 15.0);
  EXPECT_GT(far.basin_miss_px, 5.0);
  EXPECT_NE(far.reason.find("full resolution alone misses"), std::string::npos) << far.reason;
  ReuseConfig untested;
  untested.direct_basin_px = 0.0;
  EXPECT_TRUE(r.passes(untested)) << r.check(untested).reason;
}

TEST(ReactivationDirectCheck, RejectsPointsWhosePatternsAreNotTheImages) {
  // The right geometry with another place's intensities (a look-alike that passed the ORB check).
  DirectRevisit r(tangentPose(0.0, 0.0, 0.0, 0.1, 0.0, 0.0));
  std::mt19937 rng(7);
  for (std::size_t i = r.kf.points.size() - 1; i > 0; --i) {
    const std::size_t j = std::uniform_int_distribution<std::size_t>(0, i)(rng);
    std::swap(r.kf.points[i].colors, r.kf.points[j].colors);
  }
  const ReuseCheck c = r.check();
  EXPECT_FALSE(r.passes());
  EXPECT_LT(c.correlation, 0.5) << c.reason;
}

TEST(ReactivationDirectCheck, RunsAfterTheFeatureCheckOnlyWithAnImage) {
  // check() runs the direct check only when the view carries its image: without it the stage
  // after the feature check is the acceptance, with it a bad fit stops at the direct stage.
  DirectRevisit r(tangentPose(0.02, -0.04, 0.05, 0.2, -0.05, 0.25));
  r.view.T_c_w = (r.T_w_view * tangentPose(0.0, 0.04, 0.0, 0.12, 0.0, 0.0)).inverse();
  ReuseConfig no_features;
  no_features.min_feature_matches = 0;
  no_features.min_keyframe_age = 1;
  r.kf.newest_when_left = 10;
  r.record.T_w_c = SE3d();
  r.kf.path_length = 0.0;
  r.view.path_length = 10.0;
  const ReactivationSearch search(no_features);
  const ReuseCheck with_image = search.check(r.view, r.kf, r.record);
  EXPECT_FALSE(with_image.accepted);
  EXPECT_EQ(with_image.stage, ReuseStage::Direct) << with_image.reason;
  ReuseView without = r.view;
  without.pyramid = nullptr;
  const ReuseCheck c = search.check(without, r.kf, r.record);
  EXPECT_TRUE(c.accepted) << c.reason;
  EXPECT_EQ(c.stage, ReuseStage::Accepted);
  ReuseConfig off = no_features;
  off.direct_check = false;
  EXPECT_TRUE(ReactivationSearch(off).check(r.view, r.kf, r.record).accepted);
  // Asked not to align (the window has no room): it stops before the alignment, neither
  // accepted nor rejected, and nothing of the alignment is filled in.
  const ReuseCheck skipped = search.check(r.view, r.kf, r.record, /*direct=*/false);
  EXPECT_FALSE(skipped.accepted);
  EXPECT_TRUE(skipped.direct_skipped);
  EXPECT_FALSE(with_image.direct_skipped);
  EXPECT_EQ(skipped.stage, ReuseStage::Direct);
  EXPECT_EQ(skipped.direct_inliers, 0.0);
  EXPECT_EQ(skipped.correlation, 0.0);
  EXPECT_GT(with_image.direct_inliers, 0.0) << "the alignment ran when asked";
}

// The mapping stage leaves the direct check out of the search and runs it on the candidates in
// order until its window is full (MappingStage::bringBack): finishing a skipped check must give
// exactly what the check with the alignment gives, accepted or rejected.
TEST(ReactivationDirectCheck, AFinishedSkippedCheckIsTheFullCheck) {
  ReuseConfig config;
  config.min_feature_matches = 0;
  config.min_keyframe_age = 1;
  const ReactivationSearch search(config);
  for (const double off : {0.0, 0.03, 0.12}) {  // accepted, accepted further off, rejected
    DirectRevisit r(tangentPose(0.02, -0.04, 0.05, 0.2, -0.05, 0.25));
    r.view.T_c_w = (r.T_w_view * tangentPose(0.0, off / 3.0, 0.0, off, 0.0, 0.0)).inverse();
    r.kf.newest_when_left = 10;
    r.kf.path_length = 0.0;
    r.view.path_length = 10.0;
    const ReuseCheck full = search.check(r.view, r.kf, r.record);
    ReuseCheck later = search.check(r.view, r.kf, r.record, /*direct=*/false);
    ASSERT_TRUE(later.direct_skipped);
    EXPECT_EQ(search.finishCheck(r.view, r.kf, r.record, later), full.accepted) << off;
    EXPECT_FALSE(later.direct_skipped);
    EXPECT_EQ(later.accepted, full.accepted) << off;
    EXPECT_EQ(later.stage, full.stage) << off;
    EXPECT_EQ(later.direct_inliers, full.direct_inliers) << off;
    EXPECT_EQ(later.correlation, full.correlation) << off;
    EXPECT_EQ(later.shift_px, full.shift_px) << off;
    EXPECT_EQ(later.basin_miss_px, full.basin_miss_px) << off;
    EXPECT_EQ(later.outside_basin, full.outside_basin) << off;
    EXPECT_EQ(later.reason, full.reason) << off;
    EXPECT_TRUE(later.T_view_kf_aligned.matrix() == full.T_view_kf_aligned.matrix()) << off;
    if (off == 0.0) {
      EXPECT_TRUE(full.accepted) << full.reason;
    }
    if (off == 0.12) {
      EXPECT_FALSE(full.accepted);
    }
  }
}

}  // namespace
}  // namespace ldsm
