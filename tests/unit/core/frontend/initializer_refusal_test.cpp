// The initializer must refuse to initialise without real parallax: a static camera (noise and
// small vibrations), a purely rotating camera, and a real drone standing still (EuRoC).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "init_test_util.h"
#include "test_paths.h"

namespace ldsm {
namespace {

using init_test::makeIntrinsics;

constexpr double kDeg = 3.14159265358979323846 / 180.0;

/// Renders without supersampling (speed); aliasing only makes refusing harder.
init_test::InitRun runUnsampled(CoarseInitializer& init, const std::vector<SE3d>& poses,
                                const PinholeIntrinsics& K, float noise) {
  const init_test::InitScene scene = init_test::wallAndFloorScene();
  std::mt19937 rng(3);
  ImagePyramid pyramid(K.width, K.height, 5);
  init_test::InitRun run;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const ImageF image = scene.render(poses[i], K, 1, noise, &rng);
    pyramid.build(image.view());
    if (init.addFrame(pyramid, 1.0)) run.completed_at = static_cast<int>(i);
    if (init.failed()) ++run.failures;
    if (init.status() == InitStatus::kConfirming) ++run.snaps;
    run.max_flow = std::max(run.max_flow, init.lastFrameStats().flow_translation);
    run.max_parallax = std::max(run.max_parallax, init.lastFrameStats().parallax);
  }
  return run;
}

TEST(InitializerRefusal, StaticCameraWithNoiseAndVibrationNeverInitialises) {
  const PinholeIntrinsics K = makeIntrinsics(320, 240, 250);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> jitter(-1.0, 1.0);
  std::vector<SE3d> poses;
  for (int i = 0; i < 100; ++i) {
    // Vibrations: up to 0.05 degrees of rotation and 1 mm of translation (0.03 % of the depth).
    const Eigen::Vector3d w(jitter(rng), jitter(rng), jitter(rng));
    const Eigen::Vector3d t(jitter(rng), jitter(rng), jitter(rng));
    poses.emplace_back(SO3d::exp(w * 0.05 * kDeg), t * 0.001);
  }
  CoarseInitializer init(PyramidCamera(K, 5));
  const init_test::InitRun run = runUnsampled(init, poses, K, 2.f);
  std::printf("static: max flow %.2f parallax %.2f\n", run.max_flow, run.max_parallax);
  EXPECT_EQ(run.completed_at, -1);
  EXPECT_EQ(run.snaps, 0);
  EXPECT_EQ(run.failures, 0) << "a static camera is trackable";
  EXPECT_LT(run.max_flow, 0.5 * init.settings().min_parallax_flow);
  EXPECT_LT(run.max_parallax, 0.5 * init.settings().min_rotation_free_parallax);
  EXPECT_EQ(init.framesTracked(), 99);
}

TEST(InitializerRefusal, PanningCameraNeverInitialises) {
  // Pure rotation about the optical centre: 0.4 degrees per frame of yaw, some pitch.
  const PinholeIntrinsics K = makeIntrinsics(320, 240, 250);
  std::vector<SE3d> poses;
  for (int i = 0; i < 100; ++i) {
    poses.emplace_back(SO3d::exp(Eigen::Vector3d(0.1 * i, 0.4 * i, 0) * kDeg),
                       Eigen::Vector3d::Zero());
  }
  CoarseInitializer init(PyramidCamera(K, 5));
  const init_test::InitRun run = runUnsampled(init, poses, K, 1.5f);
  std::printf("panning: max flow %.2f parallax %.2f, failures %d\n", run.max_flow, run.max_parallax,
              run.failures);
  EXPECT_EQ(run.completed_at, -1);
  EXPECT_EQ(run.snaps, 0);
  // A fitted "translation" may mimic the rotation, but no rotation-free parallax appears.
  EXPECT_LT(run.max_parallax, 0.5 * init.settings().min_rotation_free_parallax);
}

TEST(InitializerRefusal, OscillatingRotationNeverInitialises) {
  // Rotation back and forth (hand-held camera turning without moving), up to 5 degrees.
  const PinholeIntrinsics K = makeIntrinsics(320, 240, 250);
  std::vector<SE3d> poses;
  for (int i = 0; i < 100; ++i) {
    const double yaw = 5.0 * std::sin(2 * 3.14159265358979 * i / 40.0);
    const double pitch = 3.0 * std::sin(2 * 3.14159265358979 * i / 27.0);
    const double roll = 2.0 * std::sin(2 * 3.14159265358979 * i / 33.0);
    poses.emplace_back(SO3d::exp(Eigen::Vector3d(pitch, yaw, roll) * kDeg),
                       Eigen::Vector3d::Zero());
  }
  CoarseInitializer init(PyramidCamera(K, 5));
  const init_test::InitRun run = runUnsampled(init, poses, K, 1.5f);
  std::printf("oscillating: max flow %.2f parallax %.2f, failures %d\n", run.max_flow,
              run.max_parallax, run.failures);
  EXPECT_EQ(run.completed_at, -1);
  EXPECT_EQ(run.snaps, 0);
  EXPECT_LT(run.max_flow, init.settings().min_parallax_flow);
  EXPECT_LT(run.max_parallax, 0.5 * init.settings().min_rotation_free_parallax);
}

TEST(InitializerRefusal, EurocDroneStandingStillNeverInitialises) {
  const std::vector<std::string> files = init_test::eurocStandingStillFrames();
  if (files.empty()) GTEST_SKIP() << "../shared/data absent: euroc_v101_static95 not available";
  ASSERT_GE(files.size(), 90u);
  const PinholeIntrinsics K = init_test::eurocCam0();
  CoarseInitializer init(PyramidCamera(K, 5));
  ImagePyramid pyramid(K.width, K.height, 5);
  ImageF image(K.width, K.height);
  double max_flow = 0;
  double max_parallax = 0;
  int snaps = 0;
  for (const std::string& f : files) {
    ASSERT_TRUE(init_test::readGrey(f, image)) << f;
    pyramid.build(image.view());
    EXPECT_FALSE(init.addFrame(pyramid, 1.0)) << f;
    if (init.status() == InitStatus::kConfirming) ++snaps;
    max_flow = std::max(max_flow, init.lastFrameStats().flow_translation);
    max_parallax = std::max(max_parallax, init.lastFrameStats().parallax);
  }
  std::printf(
      "EuRoC static: max translation flow %.2f px, parallax %.2f px, %d snapped frames, "
      "status %s\n",
      max_flow, max_parallax, snaps, toString(init.status()));
  EXPECT_EQ(snaps, 0);
  EXPECT_FALSE(init.complete());
  EXPECT_LT(max_parallax, 0.5 * init.settings().min_rotation_free_parallax);
}

}  // namespace
}  // namespace ldsm
