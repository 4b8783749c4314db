// Motion hypotheses: their construction, and tracking that recovers from a bad constant-velocity
// guess, stops early when a guess is good, and reports failure on an unrelated image.
#include "frontend/motion_hypotheses.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <set>
#include <tuple>

#include "frontend/frame_tracker.h"
#include "track_scene.h"

namespace ldsm {
namespace {

using test::TrackScene;

SE3d rotationAboutY(double angle, const Eigen::Vector3d& t = Eigen::Vector3d::Zero()) {
  return SE3d(SO3d::exp(Eigen::Vector3d(0, angle, 0)), t);
}

/// A history with a last pose and a velocity, both turned and moved.
MotionHistory movingHistory() {
  MotionHistory h;
  h.T_last_ref = SE3d(SO3d::exp(Eigen::Vector3d(0.01, 0.02, -0.01)), Eigen::Vector3d(0.1, 0, 0));
  h.T_last_prelast = SE3d(SO3d::exp(Eigen::Vector3d(0, 0.05, 0.01)), Eigen::Vector3d(0, 0.02, 0));
  h.has_velocity = true;
  return h;
}

bool near(const SE3d& a, const SE3d& b) {
  return (a.inverse() * b).log().norm() < 1e-12;
}

TEST(MotionHypothesesTest, BuildsTheExpectedPoses) {
  const MotionHistory h = movingHistory();
  const HypothesisSettings settings;
  ASSERT_EQ(motionHypothesisCount(settings), 5 + 26 * settings.rotation_angle_count);
  MotionHypothesisKind kind;
  const SE3d& V = h.T_last_prelast;
  EXPECT_TRUE(near(motionHypothesis(0, h, settings, &kind), V * h.T_last_ref));
  EXPECT_EQ(kind, MotionHypothesisKind::kConstantVelocity);
  EXPECT_TRUE(near(motionHypothesis(1, h, settings, &kind), V * V * h.T_last_ref));
  EXPECT_EQ(kind, MotionHypothesisKind::kDoubleMotion);
  const SE3d half = motionHypothesis(2, h, settings, &kind) * h.T_last_ref.inverse();
  EXPECT_TRUE(near(half * half, V));
  EXPECT_EQ(kind, MotionHypothesisKind::kHalfMotion);
  EXPECT_TRUE(near(motionHypothesis(3, h, settings, &kind), h.T_last_ref));
  EXPECT_EQ(kind, MotionHypothesisKind::kZeroMotion);
  EXPECT_TRUE(near(motionHypothesis(4, h, settings, &kind), SE3d()));
  EXPECT_EQ(kind, MotionHypothesisKind::kReferencePose);

  // Rotated hypotheses: the constant-velocity guess turned about the camera centre by each
  // configured angle in 26 distinct directions.
  const SE3d constant = V * h.T_last_ref;
  std::set<std::tuple<long, long, long>> directions;
  for (int i = 5; i < motionHypothesisCount(settings); ++i) {
    const SE3d delta = motionHypothesis(i, h, settings, &kind) * constant.inverse();
    EXPECT_EQ(kind, MotionHypothesisKind::kRotated);
    EXPECT_LT(delta.translation().norm(), 1e-12);  // a pure rotation about the camera centre
    const int angle_index = (i - 5) / 26;
    const Eigen::Vector3d w = delta.so3().log();
    EXPECT_NEAR(w.norm(), settings.rotation_angles[angle_index], 1e-12);
    const Eigen::Vector3d d = w.normalized() * 1000.0;
    directions.insert(
        {std::lround(d.x()), std::lround(d.y()), std::lround(d.z()) + 10000L * angle_index});
  }
  EXPECT_EQ(directions.size(), 26u * settings.rotation_angle_count);
}

TEST(MotionHypothesesTest, WithoutVelocityTheConstantGuessIsTheLastPose) {
  MotionHistory h;
  h.T_last_ref = SE3d(SO3d(), Eigen::Vector3d(0.1, 0.2, 0.3));
  h.T_last_prelast = SE3d(SO3d(), Eigen::Vector3d(5, 5, 5));  // ignored
  EXPECT_LT(
      (motionHypothesis(0, h, HypothesisSettings(), nullptr).inverse() * h.T_last_ref).log().norm(),
      1e-12);
}

// Frames further apart than the last two (frames dropped, a slow initializer): the guesses
// continue the last motion along its screw motion for the time that has passed.
TEST(MotionHypothesesTest, ContinuedVelocityFollowsTheTimePassed) {
  const SE3d V = movingHistory().T_last_prelast;
  // Evenly spaced (jitter within the tolerance too): the motion itself, bit for bit.
  EXPECT_EQ(FrameTracker::continuedVelocity(V, 0.2, 0.1, 0.1).matrix(), V.matrix());
  EXPECT_EQ(FrameTracker::continuedVelocity(V, 0.22, 0.1, 0.1).matrix(), V.matrix());
  // Two frames dropped: the motion three times over; a frame after half the time: half of it.
  EXPECT_TRUE(near(FrameTracker::continuedVelocity(V, 0.4, 0.1, 0.1), V * V * V));
  const SE3d half = FrameTracker::continuedVelocity(V, 0.15, 0.1, 0.1);
  EXPECT_TRUE(near(half * half, V));
}

TEST(MotionHypothesesTest, VelocityScaleIsTheTimePassedOverTheTimeTheMotionSpans) {
  EXPECT_EQ(FrameTracker::velocityScale(0.2, 0.1, 0.1), 1.0);
  EXPECT_DOUBLE_EQ(FrameTracker::velocityScale(0.4, 0.1, 0.1), 3.0);   // two frames dropped
  EXPECT_DOUBLE_EQ(FrameTracker::velocityScale(0.15, 0.1, 0.1), 0.5);  // a faster camera
  // Jitter within the tolerance of even spacing: the motion as it is.
  EXPECT_EQ(FrameTracker::velocityScale(0.22, 0.1, 0.1), 1.0);
  EXPECT_EQ(FrameTracker::velocityScale(0.18, 0.1, 0.1), 1.0);
  // At most kMaxVelocityScale; unknown or not increasing times: 1.
  EXPECT_EQ(FrameTracker::velocityScale(100.0, 0.1, 0.1), FrameTracker::kMaxVelocityScale);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(FrameTracker::velocityScale(0.4, nan, 0.1), 1.0);
  EXPECT_EQ(FrameTracker::velocityScale(0.4, 0.1, nan), 1.0);
  EXPECT_EQ(FrameTracker::velocityScale(0.1, 0.1, 0.1), 1.0);
  EXPECT_EQ(FrameTracker::velocityScale(0.0, 0.1, 0.1), 1.0);
  EXPECT_EQ(FrameTracker::velocityScale(0.4, 0.1, 0.0), 1.0);
}

// A frame farther after the last tracked one than the velocity can be continued to (more than
// kMaxVelocityScale times the time it spans) is beyond the motion model; without a velocity no
// frame is.
TEST(MotionHypothesesTest, BeyondTheMotionModelAfterTenTimesTheVelocitysSpan) {
  FrameTracker tracker(FrameTrackerSettings(), TrackScene().camera());
  FrameTracker::MotionState m = tracker.motionState();
  m.has_last = true;
  m.t_last = 2.0;
  m.velocity_dt = 0.1;
  m.has_velocity = false;
  tracker.restoreMotion(m);
  EXPECT_FALSE(tracker.beyondMotionModel(100.0));
  m.has_velocity = true;
  tracker.restoreMotion(m);
  EXPECT_DOUBLE_EQ(tracker.lastTrackedTime(), 2.0);
  EXPECT_FALSE(tracker.beyondMotionModel(2.1));
  EXPECT_FALSE(tracker.beyondMotionModel(2.5));  // four frames dropped: the scaled velocity
  EXPECT_FALSE(tracker.beyondMotionModel(2.0 + 0.1 * FrameTracker::kMaxVelocityScale));
  EXPECT_TRUE(tracker.beyondMotionModel(3.01));
  EXPECT_TRUE(tracker.beyondMotionModel(40.0));
}

TEST(MotionHypothesesTest, OverAGapTheTranslationIsContinuedAndTheRotationIsNot) {
  FrameTracker::MotionState m;
  m.has_last = true;
  m.has_velocity = true;
  m.t_last = 2.0;
  m.velocity_dt = 0.1;
  m.T_last_prelast =
      SE3d(SO3d::exp(Eigen::Vector3d(0.0, 0.003, 0.001)), Eigen::Vector3d(0.01, 0.0, 0.03));
  const FrameTracker::MotionState c = FrameTracker::continuedOverGap(m, 4.0);
  // 2 s of 0.1 s motions: 20 of them, as one motion spanning the whole gap (so that the tracker
  // takes it as it is for a frame at 4 s).
  EXPECT_TRUE(c.T_last_prelast.translation().isApprox(Eigen::Vector3d(0.2, 0.0, 0.6), 1e-12));
  EXPECT_LT(c.T_last_prelast.so3().log().norm(), 1e-15);
  EXPECT_DOUBLE_EQ(c.velocity_dt, 2.0);
  EXPECT_DOUBLE_EQ(FrameTracker::velocityScale(4.0, c.t_last, c.velocity_dt), 1.0);
  EXPECT_TRUE(near(c.T_last_w, m.T_last_w));
  // Without a velocity, or no later time: unchanged.
  FrameTracker::MotionState still = m;
  still.has_velocity = false;
  EXPECT_TRUE(near(FrameTracker::continuedOverGap(still, 4.0).T_last_prelast, m.T_last_prelast));
  EXPECT_TRUE(near(FrameTracker::continuedOverGap(m, 1.0).T_last_prelast, m.T_last_prelast));
  EXPECT_DOUBLE_EQ(FrameTracker::continuedOverGap(m, 1.0).velocity_dt, 0.1);
}

TEST(MotionHypothesesTest, TheWideSearchReachesFurtherWithTheSameDirections) {
  const HypothesisSettings normal, wide = wideHypothesisSettings();
  EXPECT_EQ(motionHypothesisCount(wide), 5 + 26 * kMaxHypothesisAngles);
  EXPECT_EQ(wide.screened_rotations, normal.screened_rotations);
  EXPECT_GT(
      wide.rotation_angles[static_cast<std::size_t>(wide.rotation_angle_count - 1)],
      2.0 * normal.rotation_angles[static_cast<std::size_t>(normal.rotation_angle_count - 1)]);
}

class HypothesisTrackingTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ImageF image, idepth;
    scene_.render(SE3d(), image, &idepth);
    const ImagePyramid ref = test::makePyramid(image);
    tracker_ = std::make_unique<CoarseTracker>(TrackScene::kWidth, TrackScene::kHeight,
                                               TrackScene::kLevels, CoarseTrackerSettings());
    tracker_->setReference(ref, scene_.camera(), test::selectPoints(image, idepth), 1.0,
                           AffineLight());
  }
  ImagePyramid renderFrame(const SE3d& T_frame_ref) {
    ImageF image;
    scene_.render(T_frame_ref.inverse(), image, nullptr);
    return test::makePyramid(image);
  }
  // One plain tracking run from `guess`: does it end at `truth`? (It may fail, or converge to a
  // wrong pose with a high residual, which the hypotheses logic then rejects.)
  bool plainTrackFinds(const ImagePyramid& frame, SE3d guess, const SE3d& truth) {
    AffineLight affine;
    CoarseTrackingResult result;
    const bool ok = tracker_->track(frame, 1.0, guess, affine, TrackScene::kLevels - 1,
                                    noAbortThresholds(), result);
    return ok && close(guess, truth) && result.rmse(0) < 1.5;
  }
  static bool close(const SE3d& a, const SE3d& b) {
    return test::rotationError(a, b) < 1e-3 && test::translationError(a, b) < 2e-3;
  }

  /// The last frame at `T_last_ref`, after the motion `T_last_prelast`, tracked at 1 grey level.
  static MotionHistory history(const SE3d& T_last_ref, const SE3d& T_last_prelast) {
    MotionHistory h;
    h.T_last_ref = T_last_ref;
    h.T_last_prelast = T_last_prelast;
    h.has_velocity = true;
    h.last_rmse = 1.0;
    return h;
  }

  TrackScene scene_;
  std::unique_ptr<CoarseTracker> tracker_;
};

TEST_F(HypothesisTrackingTest, GoodConstantVelocityGuessStopsAtOnce) {
  MotionHistory h =
      history(rotationAboutY(0.01, {0.02, 0, 0.01}), rotationAboutY(0.01, {0.02, 0, 0.01}));
  const SE3d truth = h.T_last_prelast * h.T_last_ref;
  const HypothesisTrackingResult r =
      trackWithHypotheses(*tracker_, renderFrame(truth), 1.0, h, HypothesisSettings());
  ASSERT_TRUE(r.success);
  EXPECT_EQ(r.hypothesis, 0);
  EXPECT_EQ(r.kind, MotionHypothesisKind::kConstantVelocity);
  EXPECT_EQ(r.tried, 1);
  EXPECT_TRUE(close(r.T_frame_ref, truth));
  EXPECT_DOUBLE_EQ(r.rmse, r.tracking.rmse(0));
  EXPECT_TRUE(r.tracking.success);
}

TEST_F(HypothesisTrackingTest, CameraThatStoppedIsFoundByZeroMotion) {
  MotionHistory h =
      history(rotationAboutY(0.02, {0.03, 0, 0}),
              rotationAboutY(0.15, {0.1, 0, 0}));  // fast pan ... then the camera stops
  const SE3d truth = h.T_last_ref;
  const ImagePyramid frame = renderFrame(truth);
  // The premise: the constant-velocity guess alone does not track.
  EXPECT_FALSE(plainTrackFinds(frame, h.T_last_prelast * h.T_last_ref, truth));
  const HypothesisTrackingResult r =
      trackWithHypotheses(*tracker_, frame, 1.0, h, HypothesisSettings());
  ASSERT_TRUE(r.success);
  EXPECT_GT(r.hypothesis, 0);
  EXPECT_TRUE(close(r.T_frame_ref, truth));
  EXPECT_LT(r.rmse, 1.5);
}

TEST_F(HypothesisTrackingTest, SkippedFrameIsFoundByDoubleMotion) {
  const SE3d step = rotationAboutY(0.12, {0.05, 0, 0});
  MotionHistory h = history(step, step);
  const SE3d truth = h.T_last_prelast * h.T_last_prelast * h.T_last_ref;  // a frame was dropped
  const ImagePyramid frame = renderFrame(truth);
  EXPECT_FALSE(plainTrackFinds(frame, h.T_last_prelast * h.T_last_ref, truth));
  const HypothesisTrackingResult r =
      trackWithHypotheses(*tracker_, frame, 1.0, h, HypothesisSettings());
  ASSERT_TRUE(r.success);
  EXPECT_EQ(r.kind, MotionHypothesisKind::kDoubleMotion);
  EXPECT_TRUE(close(r.T_frame_ref, truth));
}

// Three frames dropped after a fast motion: the plain constant-velocity guess (one frame's
// motion) is out of reach and so is double motion, but the guess scaled to the time that passed
// tracks at once.
TEST_F(HypothesisTrackingTest, DroppedFramesAreBridgedByTheScaledVelocity) {
  MotionHistory h =
      history(rotationAboutY(0.02, {0.02, 0, 0}), rotationAboutY(0.05, {0.03, 0, 0.01}));
  const SE3d V = h.T_last_prelast;  // a copy: h.T_last_prelast is replaced below
  const SE3d truth = V * V * V * V * h.T_last_ref;
  const ImagePyramid frame = renderFrame(truth);
  EXPECT_FALSE(plainTrackFinds(frame, V * h.T_last_ref, truth));
  EXPECT_FALSE(plainTrackFinds(frame, V * V * h.T_last_ref, truth));
  h.T_last_prelast = FrameTracker::continuedVelocity(V, 0.5, 0.1, 0.1);  // 4 frame periods on
  const HypothesisTrackingResult r =
      trackWithHypotheses(*tracker_, frame, 1.0, h, HypothesisSettings());
  ASSERT_TRUE(r.success);
  EXPECT_EQ(r.kind, MotionHypothesisKind::kConstantVelocity);
  EXPECT_EQ(r.tried, 1);
  EXPECT_TRUE(close(r.T_frame_ref, truth));
}

TEST_F(HypothesisTrackingTest, UnexpectedRotationIsFoundByRotatedHypotheses) {
  MotionHistory h;  // second frame: no velocity, last pose = reference
  h.last_rmse = 1.0;
  const SE3d truth = rotationAboutY(-0.12);
  const ImagePyramid frame = renderFrame(truth);
  EXPECT_FALSE(plainTrackFinds(frame, SE3d(), truth));
  const HypothesisTrackingResult r =
      trackWithHypotheses(*tracker_, frame, 1.0, h, HypothesisSettings());
  ASSERT_TRUE(r.success);
  EXPECT_EQ(r.kind, MotionHypothesisKind::kRotated);
  // 1..4 equal the identity guess and are skipped; every rotated one is screened at the coarsest
  // level, and only the best few are tracked to level 0.
  const HypothesisSettings settings;
  EXPECT_EQ(r.screened, 26 * settings.rotation_angle_count);
  EXPECT_LE(r.tried, 1 + settings.screened_rotations);
  EXPECT_TRUE(close(r.T_frame_ref, truth));
}

// Without rotation angles (FrameTracker::track(..., rotations = false): after a relocalisation,
// whose pose needs no rotated guesses) only the basic guesses are tracked: the same frame is then
// not found, and nothing is screened.
TEST_F(HypothesisTrackingTest, WithoutRotationAnglesOnlyTheBasicGuessesAreTried) {
  MotionHistory h;
  h.last_rmse = 1.0;
  const SE3d truth = rotationAboutY(-0.12);
  const ImagePyramid frame = renderFrame(truth);
  HypothesisSettings settings;
  settings.rotation_angle_count = 0;
  const HypothesisTrackingResult r = trackWithHypotheses(*tracker_, frame, 1.0, h, settings);
  EXPECT_EQ(r.screened, 0);
  EXPECT_LE(r.tried, 2);  // the identity guess and the reference pose (the same here)
  EXPECT_FALSE(r.success && close(r.T_frame_ref, truth));
}

// The wide search (after a loss or a gap) screens its 104 rotated guesses and ends at the turned
// frame. (This rendered scene's basin is wide enough that the ordinary search finds these turns
// too; on vamr_desk_loop after 40 noise frames it does not, and the wide one does:
// MapReuse.VamrDeskLoopResumesInItsMapAfterFortyBlackFrames.)
TEST_F(HypothesisTrackingTest, TheWideSearchFindsALargeTurn) {
  for (const Eigen::Vector3d& w : {Eigen::Vector3d(0, 0.3, 0), Eigen::Vector3d(0.17, -0.17, 0)}) {
    MotionHistory h;
    h.last_rmse = 1.0;
    SE3d::Tangent x = SE3d::Tangent::Zero();
    x.tail<3>() = w;
    const SE3d truth = SE3d::exp(x);
    const HypothesisTrackingResult wide =
        trackWithHypotheses(*tracker_, renderFrame(truth), 1.0, h, wideHypothesisSettings());
    ASSERT_TRUE(wide.success) << w.transpose();
    EXPECT_EQ(wide.kind, MotionHypothesisKind::kRotated);
    EXPECT_EQ(wide.screened, 26 * kMaxHypothesisAngles);
    EXPECT_LE(wide.tried, 1 + wideHypothesisSettings().screened_rotations);
    EXPECT_TRUE(close(wide.T_frame_ref, truth)) << w.transpose();
  }
}

TEST_F(HypothesisTrackingTest, UnscreenedSearchTriesTheRotationsInOrder) {
  MotionHistory h;
  h.last_rmse = 1.0;
  const SE3d truth = rotationAboutY(-0.12);
  HypothesisSettings settings;
  settings.screened_rotations = 0;  // DSO's search: each hypothesis in full, in order
  const HypothesisTrackingResult r =
      trackWithHypotheses(*tracker_, renderFrame(truth), 1.0, h, settings);
  ASSERT_TRUE(r.success);
  EXPECT_EQ(r.kind, MotionHypothesisKind::kRotated);
  EXPECT_EQ(r.tried, r.hypothesis + 1 - 4);  // 1..4 equal the identity guess and are skipped
  EXPECT_EQ(r.screened, 0);
  EXPECT_TRUE(close(r.T_frame_ref, truth));
}

TEST_F(HypothesisTrackingTest, ScreeningFindsWhatTheFullSearchFinds) {
  // Rotations about several axes: the screened search ends at the same pose as the full one.
  for (const Eigen::Vector3d& w : {Eigen::Vector3d(0, -0.12, 0), Eigen::Vector3d(0.06, 0, 0),
                                   Eigen::Vector3d(0.03, 0.05, 0.02)}) {
    MotionHistory h;
    h.last_rmse = 1.0;
    SE3d::Tangent x = SE3d::Tangent::Zero();
    x.tail<3>() = w;
    const SE3d truth = SE3d::exp(x);
    const ImagePyramid frame = renderFrame(truth);
    HypothesisSettings full;
    full.screened_rotations = 0;
    const HypothesisTrackingResult a = trackWithHypotheses(*tracker_, frame, 1.0, h, full);
    const HypothesisTrackingResult b =
        trackWithHypotheses(*tracker_, frame, 1.0, h, HypothesisSettings());
    ASSERT_TRUE(a.success) << w.transpose();
    ASSERT_TRUE(b.success) << w.transpose();
    EXPECT_TRUE(close(a.T_frame_ref, truth)) << w.transpose();
    EXPECT_TRUE(close(b.T_frame_ref, truth)) << w.transpose();
  }
}

TEST_F(HypothesisTrackingTest, UnrelatedImageFailsAfterTryingEverything) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> noise(0.f, 255.f);
  ImageF image(TrackScene::kWidth, TrackScene::kHeight);
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) image(x, y) = noise(rng);
  }
  const SE3d step = rotationAboutY(0.01, {0.02, 0, 0});
  const MotionHistory h = history(step, step);
  HypothesisSettings settings;
  settings.rotation_angle_count = 1;
  const HypothesisTrackingResult r =
      trackWithHypotheses(*tracker_, test::makePyramid(image), 1.0, h, settings);
  EXPECT_FALSE(r.success);
  EXPECT_EQ(r.hypothesis, -1);
  // Every basic hypothesis in full, every rotated one screened, the best few of those in full.
  EXPECT_EQ(r.screened, 26);
  EXPECT_GE(r.tried, 5);
  EXPECT_LE(r.tried, 5 + settings.screened_rotations);
  EXPECT_TRUE(std::isinf(r.rmse));
  EXPECT_TRUE(close(r.T_frame_ref, h.T_last_prelast * h.T_last_ref));  // the prediction
}

}  // namespace
}  // namespace ldsm
