// Coarse tracking on rendered views of TrackScene: known motions, brightness changes, noisy
// depth, occlusions, failures, flow indicators and bad input.
#include "frontend/coarse_tracker.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <random>
#include <vector>

#include "ldsm/error.h"
#include "track_scene.h"

namespace ldsm {
namespace {

using test::TrackScene;

SE3d makeMotion(const Eigen::Vector3d& rotation_vector, const Eigen::Vector3d& translation) {
  return SE3d(SO3d::exp(rotation_vector), translation);
}

/// A motion of about 2.5 degrees and 6.7 cm.
SE3d typicalMotion() {
  return makeMotion(Eigen::Vector3d(0.02, -0.035, 0.015), Eigen::Vector3d(0.05, -0.02, 0.04));
}

class CoarseTrackerTest : public ::testing::Test {
 protected:
  explicit CoarseTrackerTest(TrackScene::Layout layout = TrackScene::Layout::kRoomCorner)
      : scene_(layout) {}

  void SetUp() override {
    scene_.render(SE3d(), ref_image_, &ref_idepth_);
    ref_pyramid_ = std::make_unique<ImagePyramid>(test::makePyramid(ref_image_));
    points_ = test::selectPoints(ref_image_, ref_idepth_);
  }

  /// The frame seen with T_frame_ref, its intensities mapped by `transform`.
  template <typename F>
  ImagePyramid renderFrame(const SE3d& T_frame_ref, F transform) {
    ImageF image;
    scene_.render(T_frame_ref.inverse(), image, nullptr);
    for (int y = 0; y < image.height(); ++y) {
      for (int x = 0; x < image.width(); ++x) image(x, y) = transform(image(x, y));
    }
    return test::makePyramid(image);
  }
  ImagePyramid renderFrame(const SE3d& T_frame_ref) {
    return renderFrame(T_frame_ref, [](float v) { return v; });
  }

  std::unique_ptr<CoarseTracker> makeTracker(
      const std::vector<DepthPoint>& points,
      const CoarseTrackerSettings& settings = CoarseTrackerSettings()) {
    auto tracker = std::make_unique<CoarseTracker>(TrackScene::kWidth, TrackScene::kHeight,
                                                   TrackScene::kLevels, settings);
    tracker->setReference(*ref_pyramid_, scene_.camera(), points, 1.0, AffineLight());
    return tracker;
  }

  /// Tracks `frame` from the identity over all levels.
  bool trackFromIdentity(CoarseTracker& tracker, const ImagePyramid& frame, SE3d& T,
                         AffineLight& affine, CoarseTrackingResult& result, double exposure = 1.0) {
    T = SE3d();
    affine = AffineLight();
    return tracker.track(frame, exposure, T, affine, TrackScene::kLevels - 1, noAbortThresholds(),
                         result);
  }

  TrackScene scene_;
  ImageF ref_image_, ref_idepth_;
  std::unique_ptr<ImagePyramid> ref_pyramid_;
  std::vector<DepthPoint> points_;
};

class OccludingPlanesTest : public CoarseTrackerTest {
 protected:
  OccludingPlanesTest() : CoarseTrackerTest(TrackScene::Layout::kOccludingPlanes) {}
};

TEST_F(CoarseTrackerTest, SceneHasEnoughPoints) {
  EXPECT_GT(points_.size(), 1500u);
  const auto tracker = makeTracker(points_);
  for (int l = 0; l < TrackScene::kLevels; ++l) {
    EXPECT_GT(tracker->depthMaps().points(l).count, 100) << "level " << l;
  }
}

TEST_F(CoarseTrackerTest, RecoversKnownMotion) {
  const SE3d truth = typicalMotion();
  const auto tracker = makeTracker(points_);
  SE3d T;
  AffineLight affine;
  CoarseTrackingResult result;
  ASSERT_TRUE(trackFromIdentity(*tracker, renderFrame(truth), T, affine, result))
      << toString(result.failure) << " at level " << result.failed_level;
  EXPECT_LT(test::rotationError(T, truth), 1e-3);
  EXPECT_LT(test::translationError(T, truth), 0.01 * truth.translation().norm());
  EXPECT_NEAR(affine.a, 0.0, 0.01);
  EXPECT_NEAR(affine.b, 0.0, 1.5);
  EXPECT_NEAR(result.brightness_scale, 1.0, 0.01);
  EXPECT_LT(result.rmse(0), 1.5);
  EXPECT_GT(result.inlier_fraction, 0.95);
  EXPECT_GT(result.in_image_fraction, 0.8);
  EXPECT_EQ(result.failure, TrackingFailure::kNone);
  EXPECT_EQ(result.failed_level, -1);
  for (int l = 0; l < TrackScene::kLevels; ++l) EXPECT_TRUE(std::isfinite(result.rmse(l)));
}

// The coarse levels end once an accepted step lowers the cost by less than 0.1 %: level 0 starts
// close enough to reach the same pose, with fewer iterations over all than when the coarse levels
// run until a step is rejected or too small. Sensor noise on the frame and noisy depths, as on
// real images, where the coarse levels' tails of tiny improvements are long.
TEST_F(CoarseTrackerTest, CoarseLevelsStopOnceTheCostHardlyFalls) {
  const SE3d truth = typicalMotion();
  std::mt19937 rng(11);
  std::normal_distribution<float> sensor(0.f, 2.f);
  const ImagePyramid frame = renderFrame(truth, [&](float v) { return v + sensor(rng); });
  std::uniform_real_distribution<float> depth_noise(-0.05f, 0.05f);
  std::vector<DepthPoint> noisy = points_;
  for (DepthPoint& p : noisy) p.idepth *= 1.f + depth_noise(rng);
  CoarseTrackerSettings full;
  full.coarse_level_min_relative_decrease = 0.0;
  SE3d T_full, T_early;
  AffineLight affine;
  CoarseTrackingResult full_result, early_result;
  ASSERT_TRUE(trackFromIdentity(*makeTracker(noisy, full), frame, T_full, affine, full_result));
  ASSERT_TRUE(trackFromIdentity(*makeTracker(noisy), frame, T_early, affine, early_result));
  std::printf("iterations over all levels: %d run to convergence, %d with the early stop\n",
              full_result.iterations, early_result.iterations);
  EXPECT_LT(early_result.iterations, full_result.iterations);
  std::printf(
      "rotation %.2e / %.2e rad, translation %.2e / %.2e from the truth; %.2e / %.2e "
      "between them\n",
      test::rotationError(T_full, truth), test::rotationError(T_early, truth),
      test::translationError(T_full, truth), test::translationError(T_early, truth),
      test::rotationError(T_early, T_full), test::translationError(T_early, T_full));
  EXPECT_LT(test::rotationError(T_early, T_full), 2e-4);
  EXPECT_LT(test::translationError(T_early, T_full), 0.002 * truth.translation().norm());
}

// Images through a radial distortion (7.7 px at the corners): the reference's points are pixels
// of the distorted image, and the tracker told the distortion warps through it. Told none (the
// plain pinhole), the same images give a pose several times further off (measured: rotation
// 1.1e-4 against 2.9e-3 rad, translation 5.8e-4 against 1.2e-2 for a 6.7 cm motion).
TEST_F(CoarseTrackerTest, TracksThroughTheImagesRadialDistortion) {
  constexpr float k = 0.06f;
  ImageF ref_image, ref_idepth, image;
  scene_.render(SE3d(), ref_image, &ref_idepth, k);
  const ImagePyramid ref = test::makePyramid(ref_image);
  const std::vector<DepthPoint> points = test::selectPoints(ref_image, ref_idepth);
  const SE3d truth = typicalMotion();
  scene_.render(truth.inverse(), image, nullptr, k);
  const ImagePyramid frame = test::makePyramid(image);
  const auto trackWith = [&](float radial_k, SE3d& T, CoarseTrackingResult& result) {
    CoarseTracker tracker(TrackScene::kWidth, TrackScene::kHeight, TrackScene::kLevels,
                          CoarseTrackerSettings());
    tracker.setReference(ref, scene_.camera(), points, 1.0, AffineLight(), nullptr, radial_k);
    EXPECT_EQ(tracker.radialK(), radial_k);
    T = SE3d();
    AffineLight affine;
    return tracker.track(frame, 1.0, T, affine, TrackScene::kLevels - 1, noAbortThresholds(),
                         result);
  };
  SE3d T, T_pinhole;
  CoarseTrackingResult result, result_pinhole;
  ASSERT_TRUE(trackWith(k, T, result)) << toString(result.failure);
  EXPECT_LT(test::rotationError(T, truth), 1e-3);
  EXPECT_LT(test::translationError(T, truth), 0.01 * truth.translation().norm());
  EXPECT_LT(result.rmse(0), 1.5);
  EXPECT_GT(result.inlier_fraction, 0.95);
  EXPECT_GT(result.coverage, 0.9);
  trackWith(0.f, T_pinhole, result_pinhole);
  std::printf("radial: rotation %.2e translation %.2e; pinhole: rotation %.2e translation %.2e\n",
              test::rotationError(T, truth), test::translationError(T, truth),
              test::rotationError(T_pinhole, truth), test::translationError(T_pinhole, truth));
  EXPECT_GT(test::rotationError(T_pinhole, truth), 3.0 * test::rotationError(T, truth));
  EXPECT_GT(test::translationError(T_pinhole, truth), 3.0 * test::translationError(T, truth));
}

TEST_F(CoarseTrackerTest, RecoversMotionFromNearbyGuessOnFinestLevelOnly) {
  const SE3d truth = typicalMotion();
  const auto tracker = makeTracker(points_);
  SE3d::Tangent offset;
  offset << 0.003, -0.002, 0.004, 0.002, 0.001, -0.002;  // about 0.7 pixel of error
  SE3d T = SE3d::exp(offset) * truth;
  AffineLight affine;
  CoarseTrackingResult result;
  ASSERT_TRUE(tracker->track(renderFrame(truth), 1.0, T, affine, 0, noAbortThresholds(), result));
  EXPECT_LT(test::rotationError(T, truth), 1e-3);
  EXPECT_LT(test::translationError(T, truth), 0.01 * truth.translation().norm());
  EXPECT_TRUE(std::isnan(result.rmse(1)));  // coarser levels were not tracked
}

TEST_F(CoarseTrackerTest, RecoversBrightnessChange) {
  const SE3d truth = typicalMotion();
  const auto tracker = makeTracker(points_);
  SE3d T;
  AffineLight affine;
  CoarseTrackingResult result;
  ASSERT_TRUE(trackFromIdentity(*tracker, renderFrame(truth, [](float v) { return 1.3f * v + 10; }),
                                T, affine, result))
      << toString(result.failure);
  EXPECT_LT(test::rotationError(T, truth), 1e-3);
  EXPECT_LT(test::translationError(T, truth), 0.01 * truth.translation().norm());
  EXPECT_NEAR(result.brightness_scale, 1.3, 0.013);
  EXPECT_NEAR(std::exp(affine.a), 1.3, 0.013);
  EXPECT_NEAR(affine.b, 10.0, 2.0);
}

TEST_F(CoarseTrackerTest, KnownExposureRatioNeedsNoAffineChange) {
  const SE3d truth = typicalMotion();
  const auto tracker = makeTracker(points_);
  SE3d T;
  AffineLight affine;
  CoarseTrackingResult result;
  ASSERT_TRUE(trackFromIdentity(*tracker, renderFrame(truth, [](float v) { return 2.f * v; }), T,
                                affine, result, /*exposure=*/2.0));
  EXPECT_NEAR(affine.a, 0.0, 0.01);
  EXPECT_NEAR(result.brightness_scale, 2.0, 0.02);
  EXPECT_LT(test::rotationError(T, truth), 1e-3);
}

// With +-10 % noise on every inverse depth the pose stays close. The translation along the
// rotation/translation ambiguity (x translation vs. y rotation) is attenuated, as in any
// errors-in-variables regression: the scene's depth range (3.5 to 5+ m) is narrow compared with
// the noise, so the estimate is checked in image space, where tracking is judged.
TEST_F(CoarseTrackerTest, TracksWithNoisyDepth) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> noise(-0.1f, 0.1f);
  std::vector<DepthPoint> noisy = points_;
  for (DepthPoint& p : noisy) p.idepth *= 1.f + noise(rng);
  const SE3d truth = typicalMotion();
  const auto tracker = makeTracker(noisy);
  SE3d T;
  AffineLight affine;
  CoarseTrackingResult result;
  ASSERT_TRUE(trackFromIdentity(*tracker, renderFrame(truth), T, affine, result))
      << toString(result.failure);
  EXPECT_LT(test::rotationError(T, truth), 3e-3);
  EXPECT_LT(test::translationError(T, truth), 0.25 * truth.translation().norm());
  // Reprojection of the exact points: estimated vs. true pose, in pixels.
  const LevelCamera cam = scene_.camera()[0];
  double sum = 0;
  for (const DepthPoint& p : points_) {
    const Eigen::Vector3d X =
        Eigen::Vector3d((p.u - cam.cx) / cam.fx, (p.v - cam.cy) / cam.fy, 1.0) / p.idepth;
    const Eigen::Vector3d a = T * X, b = truth * X;
    sum += (cam.fx * Eigen::Vector2d(a.x() / a.z() - b.x() / b.z(), a.y() / a.z() - b.y() / b.z()))
               .norm();
  }
  EXPECT_LT(sum / points_.size(), 0.2);
}

// Occluded points are outliers; the remaining bias stays small.
TEST_F(OccludingPlanesTest, TracksDespiteOcclusions) {
  const SE3d truth = typicalMotion();
  const auto tracker = makeTracker(points_);
  SE3d T;
  AffineLight affine;
  CoarseTrackingResult result;
  ASSERT_TRUE(trackFromIdentity(*tracker, renderFrame(truth), T, affine, result))
      << toString(result.failure);
  EXPECT_LT(test::rotationError(T, truth), 2e-3);
  EXPECT_LT(test::translationError(T, truth), 0.1 * truth.translation().norm());
  EXPECT_LT(result.inlier_fraction, 1.0);  // there are occlusions
}

TEST_F(CoarseTrackerTest, NoiseImageIsFailure) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> noise(0.f, 255.f);
  ImageF image(TrackScene::kWidth, TrackScene::kHeight);
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) image(x, y) = noise(rng);
  }
  const auto tracker = makeTracker(points_);
  SE3d T;
  AffineLight affine;
  CoarseTrackingResult result;
  EXPECT_FALSE(trackFromIdentity(*tracker, test::makePyramid(image), T, affine, result));
  EXPECT_FALSE(result.success);
  EXPECT_NE(result.failure, TrackingFailure::kNone);
  EXPECT_GE(result.failed_level, 0);
}

TEST_F(CoarseTrackerTest, FlowIndicatorsSeparateRotationAndTranslation) {
  const auto tracker = makeTracker(points_);
  const LevelPoints& pts = tracker->depthMaps().points(0);
  const LevelCamera cam = scene_.camera()[0];
  // Root-mean-square shift of the level-0 points under T (computed here independently).
  const auto expectedFlow = [&](const SE3d& T) {
    double sum = 0;
    for (int i = 0; i < pts.count; ++i) {
      const Eigen::Vector3d p =
          Eigen::Vector3d((pts.x[i] - cam.cx) / cam.fx, (pts.y[i] - cam.cy) / cam.fy, 1.0) /
          pts.idepth[i];
      const Eigen::Vector3d q = T * p;
      const double du = cam.fx * q.x() / q.z() + cam.cx - pts.x[i];
      const double dv = cam.fy * q.y() / q.z() + cam.cy - pts.y[i];
      sum += du * du + dv * dv;
    }
    return std::sqrt(sum / pts.count);
  };
  const SE3d rotation = makeMotion(Eigen::Vector3d(0.01, -0.03, 0.01), Eigen::Vector3d::Zero());
  const SE3d translation = makeMotion(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.06, 0.02, 0.05));
  const SE3d both = typicalMotion();
  for (const SE3d& truth : {rotation, translation, both}) {
    SE3d T;
    AffineLight affine;
    CoarseTrackingResult result;
    ASSERT_TRUE(trackFromIdentity(*tracker, renderFrame(truth), T, affine, result));
    const SE3d rot_only(truth.so3(), Eigen::Vector3d::Zero());
    const SE3d trans_only(SO3d(), truth.translation());
    const double tol = 0.01 * expectedFlow(truth) + 0.01;
    EXPECT_NEAR(result.flow_full, expectedFlow(truth), tol);
    EXPECT_NEAR(result.flow_rotation, expectedFlow(rot_only), tol);
    EXPECT_NEAR(result.flow_translation, expectedFlow(trans_only), tol);
  }
}

TEST_F(CoarseTrackerTest, CoverageFallsAsTheCameraBacksAway) {
  const auto tracker = makeTracker(points_);
  const LevelPoints& pts = tracker->depthMaps().points(0);
  const LevelCamera cam = scene_.camera()[0];
  // Share of 16 x 12 image cells holding a reference point after T, over those holding one in
  // the reference (computed here independently, from every point).
  const auto expectedCoverage = [&](const SE3d& T) {
    std::vector<char> before(16 * 12, 0), after(16 * 12, 0);
    const auto mark = [&](std::vector<char>& cells, double u, double v) {
      if (u < 0 || v < 0 || u >= cam.width || v >= cam.height) return;
      cells[static_cast<int>(v * 12 / cam.height) * 16 + static_cast<int>(u * 16 / cam.width)] = 1;
    };
    for (int i = 0; i < pts.count; ++i) {
      const Eigen::Vector3d p =
          Eigen::Vector3d((pts.x[i] - cam.cx) / cam.fx, (pts.y[i] - cam.cy) / cam.fy, 1.0) /
          pts.idepth[i];
      const Eigen::Vector3d q = T * p;
      mark(before, pts.x[i], pts.y[i]);
      if (q.z() > 0) mark(after, cam.fx * q.x() / q.z() + cam.cx, cam.fy * q.y() / q.z() + cam.cy);
    }
    return static_cast<double>(std::count(after.begin(), after.end(), 1)) /
           std::count(before.begin(), before.end(), 1);
  };
  double last = 1.0;
  for (const double back : {0.0, 0.6, 0.9}) {
    // The frame's camera behind the reference's (the walls are 3-6 m away): the reference's
    // points gather towards the centre of the frame and leave its borders empty.
    const SE3d truth = makeMotion(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.0, 0.0, back));
    SE3d T;
    AffineLight affine;
    CoarseTrackingResult result;
    ASSERT_TRUE(trackFromIdentity(*tracker, renderFrame(truth), T, affine, result)) << back;
    EXPECT_NEAR(result.coverage, expectedCoverage(truth), 0.03) << back;
    if (back == 0.0) {
      EXPECT_NEAR(result.coverage, 1.0, 0.01);
    } else {
      EXPECT_LT(result.coverage, last - 0.02) << back;
    }
    last = result.coverage;
  }
  EXPECT_LT(last, 0.9);  // far enough back for a new keyframe by default
}

TEST_F(CoarseTrackerTest, AbortThresholdStopsAtCoarsestLevel) {
  const auto tracker = makeTracker(points_);
  SE3d T;
  AffineLight affine;
  CoarseTrackingResult result;
  LevelValues max_rmse = noAbortThresholds();
  max_rmse(TrackScene::kLevels - 1) = 0.01;
  EXPECT_FALSE(tracker->track(renderFrame(typicalMotion()), 1.0, T, affine, TrackScene::kLevels - 1,
                              max_rmse, result));
  EXPECT_EQ(result.failure, TrackingFailure::kResidualTooLarge);
  EXPECT_EQ(result.failed_level, TrackScene::kLevels - 1);
  EXPECT_TRUE(std::isnan(result.rmse(TrackScene::kLevels - 2)));
}

TEST_F(CoarseTrackerTest, PointsLeavingTheImageIsFailure) {
  const auto tracker = makeTracker(points_);
  const ImagePyramid frame = renderFrame(SE3d());
  SE3d T = makeMotion(Eigen::Vector3d::Zero(), Eigen::Vector3d(20.0, 0, 0));
  AffineLight affine;
  CoarseTrackingResult result;
  EXPECT_FALSE(tracker->track(frame, 1.0, T, affine, 2, noAbortThresholds(), result));
  EXPECT_EQ(result.failure, TrackingFailure::kTooFewInImage);
  EXPECT_EQ(result.failed_level, 2);
}

TEST_F(CoarseTrackerTest, TrackingWithoutReferenceIsFailure) {
  CoarseTracker tracker(TrackScene::kWidth, TrackScene::kHeight, TrackScene::kLevels,
                        CoarseTrackerSettings());
  EXPECT_FALSE(tracker.hasReference());
  SE3d T;
  AffineLight affine;
  CoarseTrackingResult result;
  EXPECT_FALSE(trackFromIdentity(tracker, renderFrame(SE3d()), T, affine, result));
  EXPECT_EQ(result.failure, TrackingFailure::kNoReference);
}

TEST_F(CoarseTrackerTest, EmptyReferenceIsFailure) {
  const auto tracker = makeTracker({});
  SE3d T;
  AffineLight affine;
  CoarseTrackingResult result;
  EXPECT_FALSE(trackFromIdentity(*tracker, renderFrame(SE3d()), T, affine, result));
  EXPECT_EQ(result.failure, TrackingFailure::kNoReference);
}

TEST_F(CoarseTrackerTest, RejectsBadInput) {
  const auto tracker = makeTracker(points_);
  SE3d T;
  AffineLight affine;
  CoarseTrackingResult result;
  ImageF small(TrackScene::kWidth / 2, TrackScene::kHeight / 2, 100.f);
  ImagePyramid small_pyramid(small.width(), small.height(), 4);
  small_pyramid.build(small.view());
  EXPECT_THROW(tracker->track(small_pyramid, 1.0, T, affine, 4, noAbortThresholds(), result),
               InputError);
  const ImagePyramid frame = renderFrame(SE3d());
  EXPECT_THROW(tracker->track(frame, 0.0, T, affine, 4, noAbortThresholds(), result), InputError);
  EXPECT_THROW(tracker->track(frame, std::nan(""), T, affine, 4, noAbortThresholds(), result),
               InputError);
  EXPECT_THROW(tracker->setReference(*ref_pyramid_, scene_.camera(), points_, -1.0, AffineLight()),
               InputError);
  PinholeIntrinsics wrong = scene_.intrinsics();
  wrong.width = 640;
  EXPECT_THROW(tracker->setReference(*ref_pyramid_, PyramidCamera(wrong, TrackScene::kLevels),
                                     points_, 1.0, AffineLight()),
               InputError);
  EXPECT_THROW(tracker->setReference(*ref_pyramid_, scene_.camera(), points_, 1.0, AffineLight(),
                                     nullptr, std::numeric_limits<float>::quiet_NaN()),
               InputError);
  EXPECT_THROW(tracker->setReference(small_pyramid, scene_.camera(), points_, 1.0, AffineLight()),
               InputError);
  // Points outside the image or with bad inverse depth are skipped, not used.
  std::vector<DepthPoint> bad = {{-5.f, 10.f, 0.2f, 1.f},
                                 {10.f, 10.f, std::nanf(""), 1.f},
                                 {10.f, 10.f, -0.2f, 1.f},
                                 {10.f, 10.f, 0.2f, 0.f}};
  tracker->setReference(*ref_pyramid_, scene_.camera(), bad, 1.0, AffineLight());
  EXPECT_EQ(tracker->depthMaps().rejectedPoints(), 4);
  EXPECT_EQ(tracker->depthMaps().points(0).count, 0);
}

TEST(CoarseTrackerSettingsTest, RejectsBadThresholds) {
  CoarseTrackerSettings s;
  s.huber_threshold = 0.f;
  EXPECT_THROW(CoarseTracker(64, 48, 3, s), ConfigError);
  s = CoarseTrackerSettings();
  s.outlier_threshold = std::nanf("");
  EXPECT_THROW(CoarseTracker(64, 48, 3, s), ConfigError);
  EXPECT_THROW(CoarseTracker(64, 48, 9, CoarseTrackerSettings()), ConfigError);
  s = CoarseTrackerSettings();
  s.coarse_level_min_relative_decrease = -0.1;
  EXPECT_THROW(CoarseTracker(64, 48, 3, s), ConfigError);
  s.coarse_level_min_relative_decrease = 1.0;
  EXPECT_THROW(CoarseTracker(64, 48, 3, s), ConfigError);
}

}  // namespace
}  // namespace ldsm

namespace ldsm {
namespace {

// A guess far from the truth invites the degenerate "solution" of flattening the contrast
// (scale -> 0, offset -> mean), which lowers the residual without aligning anything. The
// brightness-change prior keeps the affine parameters near the prediction in that case.
class AffinePriorTest : public CoarseTrackerTest {
 protected:
  double finalAffineA(double prior_a) {
    CoarseTrackerSettings s;
    s.affine_change_prior_a = prior_a;
    s.affine_change_prior_b = prior_a > 0.0 ? 0.01 : 0.0;
    const auto tracker = makeTracker(points_, s);
    const SE3d truth(SO3d::exp(Eigen::Vector3d(0.0, 0.25, 0.05)), Eigen::Vector3d(0.2, 0, 0));
    SE3d T;
    AffineLight affine;
    CoarseTrackingResult result;
    trackFromIdentity(*tracker, renderFrame(truth), T, affine, result);
    return affine.a;
  }
};

TEST_F(AffinePriorTest, WrongGuessDoesNotFlattenTheContrast) {
  // Premise: without the prior, the wrong guess drives the contrast scale far down.
  EXPECT_LT(finalAffineA(0.0), -0.5);
  EXPECT_GT(finalAffineA(CoarseTrackerSettings().affine_change_prior_a), -0.2);
}

}  // namespace
}  // namespace ldsm
