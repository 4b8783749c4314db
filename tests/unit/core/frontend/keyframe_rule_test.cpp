// The keyframe rule of FrameTracker: a frame that fits its reference with few inliers makes a
// keyframe (KeyframeConfig::min_inlier_fraction), even when the camera hardly moved and the fit is
// no worse than the first frame's against that reference.
#include <gtest/gtest.h>

#include <memory>
#include <random>

#include "frontend/frame_tracker.h"
#include "track_scene.h"

namespace ldsm {
namespace {

using test::TrackScene;

class KeyframeRuleTest : public ::testing::Test {
 protected:
  TrackScene scene_;
  ImageF ref_image_, ref_idepth_;

  KeyframeRuleTest() { scene_.render(SE3d(), ref_image_, &ref_idepth_); }

  /// A tracker with the reference view as keyframe 0 at the world origin, last frame at it.
  std::unique_ptr<FrameTracker> makeTracker(const FrameTrackerSettings& settings) {
    auto tracker = std::make_unique<FrameTracker>(settings, scene_.camera());
    std::unique_ptr<CoarseTracker> prepared = tracker->makeCoarseTracker();
    prepared->setReference(test::makePyramid(ref_image_), scene_.camera(),
                           test::selectPoints(ref_image_, ref_idepth_), 1.0, AffineLight());
    tracker->adoptReference(prepared, 0, SE3d(), false);
    tracker->resetMotion(SE3d(), AffineLight(), 0.0);
    return tracker;
  }

  /// The view 2 mm to the side; `occluded` of its width, from the right, covered by noise (an
  /// object in front of the camera).
  ImagePyramid frame(double occluded) const {
    ImageF image;
    scene_.render(SE3d(SO3d(), Eigen::Vector3d(0.002, 0.0, 0.0)), image, nullptr);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> grey(20.f, 235.f);
    const int x0 = static_cast<int>((1.0 - occluded) * image.width());
    for (int y = 0; y < image.height(); ++y)
      for (int x = x0; x < image.width(); ++x) image(x, y) = grey(rng);
    return test::makePyramid(image);
  }
};

TEST_F(KeyframeRuleTest, AFrameWithFewInliersMakesAKeyframe) {
  FrameTrackerSettings settings;
  // Unoccluded: tracked with nearly every point an inlier, no keyframe (the camera hardly moved).
  const FrameTrackingOutcome clear = makeTracker(settings)->track(frame(0.0), 1.0, 0.1);
  ASSERT_TRUE(clear.success) << clear.failure;
  EXPECT_GT(clear.inlier_fraction, 0.95);
  EXPECT_FALSE(clear.wants_keyframe);
  // Half the view covered: still tracked (the rest holds the pose), with 57 % of the points
  // inliers (noise matches some patterns by chance), and that makes a keyframe.
  const FrameTrackingOutcome covered = makeTracker(settings)->track(frame(0.52), 1.0, 0.1);
  ASSERT_TRUE(covered.success) << covered.failure;
  EXPECT_LT(covered.inlier_fraction, settings.keyframes.min_inlier_fraction);
  EXPECT_GT(covered.inlier_fraction, 0.5);
  EXPECT_TRUE(covered.wants_keyframe);
  // The rule off: the same frame makes none.
  settings.keyframes.min_inlier_fraction = 0.0;
  const FrameTrackingOutcome off = makeTracker(settings)->track(frame(0.52), 1.0, 0.1);
  ASSERT_TRUE(off.success) << off.failure;
  EXPECT_FALSE(off.wants_keyframe);
}

}  // namespace
}  // namespace ldsm
