// Coarse tracking on rendered views of TrackScene: known motions, brightness changes, noisy
// depth, failures, flow indicators and bad input.
#include "frontend/coarse_tracker.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "ldsm/error.h"
#include "track_scene.h"

namespace ldsm {
namespace {

using test::TrackScene;

SE3d makeMotion(const Eigen::Vector3d& rotation_vector, const Eigen::Vector3d& translation) {
  return SE3d(SO3d::exp(rotation_vector), translation);
}

class CoarseTrackerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    scene_.render(SE3d(), ref_image_, &ref_idepth_);
    ref_pyramid_ = std::make_unique<ImagePyramid>(test::makePyramid(ref_image_));
    points_ = test::selectPoints(ref_image_, ref_idepth_);
  }

  /// Renders the frame seen with T_frame_ref and builds its pyramid; `transform` maps the
  /// intensity (brightness changes).
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

  CoarseTracker makeTracker(const std::vector<DepthPoint>& points,
                            const CoarseTrackerSettings& settings = CoarseTrackerSettings()) {
    CoarseTracker tracker(TrackScene::kWidth, TrackScene::kHeight, TrackScene::kLevels, settings);
    tracker.setReference(*ref_pyramid_, scene_.camera(), points, 1.0, AffineLight());
    return tracker;
  }

  TrackScene scene_;
  ImageF ref_image_, ref_idepth_;
  std::unique_ptr<ImagePyramid> ref_pyramid_;
  std::vector<DepthPoint> points_;
};

TEST_F(CoarseTrackerTest, SceneHasEnoughPoints) {
  EXPECT_GT(points_.size(), 1500u);
  EXPECT_LT(points_.size(), 5000u);
}

TEST_F(CoarseTrackerTest, RecoversKnownMotion) {
  const SE3d truth = makeMotion(Eigen::Vector3d(0.02, -0.035, 0.015),
                                Eigen::Vector3d(0.05, -0.02, 0.04));
  const ImagePyramid frame = renderFrame(truth);
  CoarseTracker tracker = makeTracker(points_);
  SE3d T;
  AffineLight affine;
  CoarseTrackingResult result;
  ASSERT_TRUE(tracker.track(frame, 1.0, T, affine, TrackScene::kLevels - 1, noAbortThresholds(),
                            result))
      << toString(result.failure) << " at level " << result.failed_level;
  EXPECT_LT(test::rotationError(T, truth), 1e-3);
  EXPECT_LT(test::translationError(T, truth), 0.01 * truth.translation().norm());
  EXPECT_NEAR(affine.a, 0.0, 0.01);
  EXPECT_NEAR(affine.b, 0.0, 1.0);
  EXPECT_LT(result.rmse(0), 2.0);
  EXPECT_GT(result.inlier_fraction, 0.9);
  std::printf("rot err %g trans err %g rmse %g %g %g %g %g it %d\n", test::rotationError(T, truth),
              test::translationError(T, truth), result.rmse(0), result.rmse(1), result.rmse(2),
              result.rmse(3), result.rmse(4), result.iterations);
}

}  // namespace
}  // namespace ldsm
namespace ldsm {
namespace {
TEST_F(CoarseTrackerTest, DebugAtTruth) {
  const SE3d truth = makeMotion(Eigen::Vector3d(0.02, -0.035, 0.015),
                                Eigen::Vector3d(0.05, -0.02, 0.04));
  const ImagePyramid frame = renderFrame(truth);
  CoarseTrackerSettings s;
  s.max_iterations.fill(0);
  CoarseTracker tracker = makeTracker(points_, s);
  for (int l = 0; l < 5; ++l) std::printf("level %d points %d\n", l, tracker.depthMaps().points(l).count);
  SE3d T = truth;
  AffineLight affine;
  CoarseTrackingResult result;
  tracker.track(frame, 1.0, T, affine, 4, noAbortThresholds(), result);
  std::printf("at truth: rmse %g %g %g %g %g inl %g\n", result.rmse(0), result.rmse(1), result.rmse(2),
              result.rmse(3), result.rmse(4), result.inlier_fraction);
  CoarseTracker t2 = makeTracker(points_);
  T = truth; affine = AffineLight();
  t2.track(frame, 1.0, T, affine, 0, noAbortThresholds(), result);
  std::printf("from truth lvl0: rot %g trans %g a %g b %g rmse %g\n", test::rotationError(T, truth),
              test::translationError(T, truth), affine.a, affine.b, result.rmse(0));
}
}
}
namespace ldsm {
namespace {
TEST_F(CoarseTrackerTest, DebugResiduals) {
  const SE3d truth = makeMotion(Eigen::Vector3d(0.02, -0.035, 0.015),
                                Eigen::Vector3d(0.05, -0.02, 0.04));
  const ImagePyramid frame = renderFrame(truth);
  CoarseTracker tracker = makeTracker(points_);
  const LevelPoints& P = tracker.depthMaps().points(0);
  int hist[6] = {0}; int bad_depth = 0; int bad_depth_large = 0; double s2_good = 0; int n_good = 0;
  for (int i = 0; i < P.count; ++i) {
    float r;
    if (!tracker.pointResidual(frame, 1.0, truth, AffineLight(), 0, i, &r, nullptr)) continue;
    const float true_id = ref_idepth_(int(P.x[i]), int(P.y[i]));
    const bool depth_ok = std::abs(P.idepth[i] - true_id) < 0.002f;
    const float a = std::abs(r);
    int b = a < 0.5 ? 0 : a < 1 ? 1 : a < 2 ? 2 : a < 5 ? 3 : a < 9 ? 4 : 5;
    hist[b]++;
    if (!depth_ok) { bad_depth++; if (a > 2) bad_depth_large++; }
    else { s2_good += a * a; n_good++; }
  }
  std::printf("hist <0.5 %d <1 %d <2 %d <5 %d <9 %d >9 %d; bad depth %d (large r %d); rms good-depth %g\n",
              hist[0], hist[1], hist[2], hist[3], hist[4], hist[5], bad_depth, bad_depth_large, std::sqrt(s2_good / n_good));
}
}
}
namespace ldsm {
namespace {
TEST_F(CoarseTrackerTest, DebugNoOcclusion) {
  const SE3d truth = makeMotion(Eigen::Vector3d(0.02, -0.035, 0.015),
                                Eigen::Vector3d(0.05, -0.02, 0.04));
  const ImagePyramid frame = renderFrame(truth);
  ImageF fimg, fid;
  scene_.render(truth.inverse(), fimg, &fid);
  const LevelCamera cam = scene_.camera()[0];
  std::vector<DepthPoint> vis;
  for (const DepthPoint& p : points_) {
    Eigen::Vector3d X = Eigen::Vector3d((p.u - cam.cx) / cam.fx, (p.v - cam.cy) / cam.fy, 1) / p.idepth;
    Eigen::Vector3d q = truth * X;
    int u = int(std::floor(cam.fx * q.x() / q.z() + cam.cx + 0.5)), v = int(std::floor(cam.fy * q.y() / q.z() + cam.cy + 0.5));
    if (u < 0 || v < 0 || u >= 320 || v >= 240) continue;
    bool ok = true;
    for (int dy = -3; dy <= 3; ++dy) for (int dx = -3; dx <= 3; ++dx) {
      int uu = std::clamp(u + dx, 0, 319), vv = std::clamp(v + dy, 0, 239);
      if (std::abs(fid(uu, vv) * q.z() - 1) > 0.05) ok = false;
    }
    if (ok) vis.push_back(p);
  }
  std::printf("visible %zu of %zu\n", vis.size(), points_.size());
  for (int variant = 0; variant < 2; ++variant) {
    CoarseTracker tracker = makeTracker(variant ? vis : points_);
    SE3d T; AffineLight affine; CoarseTrackingResult result;
    tracker.track(frame, 1.0, T, affine, 4, noAbortThresholds(), result);
    std::printf("%s: rot %g trans %g a %g b %g rmse %g inl %g\n", variant ? "visible" : "all", test::rotationError(T, truth),
              test::translationError(T, truth), affine.a, affine.b, result.rmse(0), result.inlier_fraction);
  }
}
}
}
