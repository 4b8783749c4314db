// The initializer on rendered sequences: a translating camera initialises within a few tens of
// frames with depths and motion matching the truth up to scale.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <ostream>
#include <random>
#include <string>
#include <vector>

#include "init_test_util.h"
#include "ldsm/config.h"
#include "ldsm/error.h"
#include "pipeline/stage_settings.h"

namespace ldsm {
namespace {

using init_test::InitRun;
using init_test::InitScene;
using init_test::makeIntrinsics;

constexpr double kDeg = 3.14159265358979323846 / 180.0;

/// Camera-to-world poses: position step `velocity` per frame, yaw `yaw_rate` rad per frame.
std::vector<SE3d> linearMotion(const Eigen::Vector3d& velocity, double yaw_rate, int frames) {
  std::vector<SE3d> poses;
  for (int i = 0; i < frames; ++i) {
    const SO3d R = SO3d::exp(Eigen::Vector3d(0, yaw_rate * i, 0));
    poses.emplace_back(R, velocity * static_cast<double>(i));
  }
  return poses;
}

struct Accuracy {
  double median_rel_error = 1;
  double translation_angle_deg = 180;
  double rotation_error_deg = 180;
  int good_points = 0;
};

Accuracy compareWithTruth(const InitializationResult& r, const InitScene& scene,
                          const PinholeIntrinsics& K, const SE3d& T_w_ref, const SE3d& T_w_frame) {
  Accuracy acc;
  std::vector<double> ratios, truth, est;
  for (const InitializedPoint& p : r.points) {
    if (!p.good) continue;
    const double d_true = scene.inverseDepth(T_w_ref, K, p.u, p.v);
    if (d_true <= 0) continue;
    truth.push_back(d_true);
    est.push_back(p.idepth);
    ratios.push_back(d_true / p.idepth);
  }
  acc.good_points = static_cast<int>(truth.size());
  if (ratios.empty()) return acc;
  std::vector<double> sorted = ratios;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double scale = sorted[sorted.size() / 2];
  std::vector<double> errors;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    errors.push_back(std::abs(scale * est[i] - truth[i]) / truth[i]);
  }
  std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
  acc.median_rel_error = errors[errors.size() / 2];

  const SE3d T_true = T_w_frame.inverse() * T_w_ref;
  const Eigen::Vector3d t_true = T_true.translation();
  const Eigen::Vector3d t_est = r.T_frame_ref.translation();
  acc.translation_angle_deg =
      std::acos(std::clamp(t_true.normalized().dot(t_est.normalized()), -1.0, 1.0)) / kDeg;
  acc.rotation_error_deg = (T_true.so3().inverse() * r.T_frame_ref.so3()).angle() / kDeg;
  return acc;
}

struct MotionCase {
  const char* name;
  Eigen::Vector3d velocity;  ///< metres per frame
  double yaw_rate_deg;
};

void PrintTo(const MotionCase& c, std::ostream* os) {
  *os << c.name;
}

class TranslatingCamera : public ::testing::TestWithParam<MotionCase> {};

TEST_P(TranslatingCamera, InitialisesWithDepthsMatchingTruth) {
  const MotionCase& c = GetParam();
  const PinholeIntrinsics K = makeIntrinsics(320, 240, 250);
  const InitScene scene = init_test::wallAndFloorScene();
  const std::vector<SE3d> poses = linearMotion(c.velocity, c.yaw_rate_deg * kDeg, 40);
  CoarseInitializer init(PyramidCamera(K, 5));
  const InitRun run = init_test::runSequence(init, scene, poses, K, 1.5f, 7, true);

  ASSERT_GE(run.completed_at, 8) << "initialised too early: the parallax cannot be real yet";
  ASSERT_LE(run.completed_at, 32) << "did not initialise within 32 frames";
  EXPECT_EQ(run.failures, 0);
  const InitializationResult& r = init.result();
  EXPECT_EQ(r.frames, run.completed_at);
  const Accuracy acc =
      compareWithTruth(r, scene, K, poses.front(), poses[static_cast<std::size_t>(r.frames)]);
  std::printf(
      "%s: done at frame %d, %d good points, median depth error %.2f %%, translation "
      "direction error %.2f deg, rotation error %.3f deg, %.1f ms/frame\n",
      c.name, run.completed_at, acc.good_points, 100 * acc.median_rel_error,
      acc.translation_angle_deg, acc.rotation_error_deg, run.ms_per_frame);
  EXPECT_GT(acc.good_points, 300);
  EXPECT_LT(acc.median_rel_error, 0.05);
  EXPECT_LT(acc.translation_angle_deg, 3.0);
  EXPECT_LT(acc.rotation_error_deg, 0.3);

  // Scale normalised: mean inverse depth of the good points is 1.
  double sum = 0;
  int n = 0;
  for (const InitializedPoint& p : r.points) {
    if (p.good) {
      sum += p.idepth;
      ++n;
    }
  }
  EXPECT_NEAR(sum / n, 1.0, 1e-3);
}

TEST(TranslatingCameraVga, InitialisesAt640x480) {
  // The size the timing budget is given for (< 30 ms per frame, single thread); the CPU time is
  // printed, not asserted (it depends on the machine).
  const PinholeIntrinsics K = makeIntrinsics(640, 480, 500);
  const InitScene scene = init_test::wallAndFloorScene();
  const std::vector<SE3d> poses = linearMotion({0.01, 0.002, 0.004}, 0.03 * kDeg, 30);
  CoarseInitializer init(PyramidCamera(K, 5));
  const InitRun run = init_test::runSequence(init, scene, poses, K, 1.5f, 9, true);
  ASSERT_GE(run.completed_at, 5);
  ASSERT_LE(run.completed_at, 25);
  const InitializationResult& r = init.result();
  const Accuracy acc =
      compareWithTruth(r, scene, K, poses.front(), poses[static_cast<std::size_t>(r.frames)]);
  std::printf(
      "640x480: done at frame %d, %d good points, median depth error %.2f %%, "
      "translation direction error %.2f deg, %.1f ms CPU per frame\n",
      run.completed_at, acc.good_points, 100 * acc.median_rel_error, acc.translation_angle_deg,
      run.ms_per_frame);
  EXPECT_LT(acc.median_rel_error, 0.05);
  EXPECT_LT(acc.translation_angle_deg, 3.0);
  int corners = 0;
  for (const InitializedPoint& p : r.points) corners += p.is_corner ? 1 : 0;
  EXPECT_GT(corners, 0) << "level-0 points come from the PixelSelector, with its corners";
}

/// Sideways motion with the image brightness changing as I' = gain * I + offset, the gain given
/// to the initializer as the exposure or not.
void runBrightnessChange(bool exposure_known) {
  const PinholeIntrinsics K = makeIntrinsics(320, 240, 250);
  const InitScene scene = init_test::wallAndFloorScene();
  const std::vector<SE3d> poses = linearMotion({0.012, 0, 0.003}, 0.0, 40);
  CoarseInitializer init(PyramidCamera(K, 5),
                         coarseInitializerSettings(Config{}, 5, exposure_known));
  std::mt19937 rng(21);
  ImagePyramid pyramid(K.width, K.height, 5);
  int done_at = -1;
  double gain = 1, offset = 0;
  for (std::size_t i = 0; i < poses.size() && done_at < 0; ++i) {
    gain = 1.0 + 0.02 * static_cast<double>(i);
    offset = exposure_known ? 0.0 : -0.8 * static_cast<double>(i);
    ImageF image = scene.render(poses[i], K, 2, 1.5f, &rng);
    for (int y = 0; y < K.height; ++y) {
      for (int x = 0; x < K.width; ++x) {
        image(x, y) = static_cast<float>(gain * image(x, y) + offset);
      }
    }
    pyramid.build(image.view());
    if (init.addFrame(pyramid, exposure_known ? gain : 1.0)) done_at = static_cast<int>(i);
    ASSERT_FALSE(init.failed()) << "frame " << i << ": " << toString(init.failure());
  }
  ASSERT_GE(done_at, 5);
  ASSERT_LE(done_at, 30);
  const InitializationResult& r = init.result();
  const Accuracy acc =
      compareWithTruth(r, scene, K, poses.front(), poses[static_cast<std::size_t>(r.frames)]);
  EXPECT_LT(acc.median_rel_error, 0.05);
  EXPECT_LT(acc.translation_angle_deg, 3.0);
  // Gain and offset trade off against each other (and against sub-pixel depth shifts on smooth
  // texture), so check the brightness transfer s I + b where the image content is (mid-grey)
  // and the gain.
  const double s_est = std::exp(r.affine_frame.a) * r.exposure_frame / r.exposure_ref;
  const double mid = 128;
  EXPECT_NEAR(s_est * mid + r.affine_frame.b, gain * mid + offset, 1.5);
  EXPECT_NEAR(s_est, gain, 0.05 * gain);
  if (exposure_known) {
    EXPECT_DOUBLE_EQ(r.exposure_frame, gain);
    EXPECT_NEAR(r.affine_frame.a, 0.0, 0.02) << "the known exposure explains the gain";
  } else {
    EXPECT_DOUBLE_EQ(r.exposure_frame, 1.0);
  }
  std::printf(
      "brightness (exposure %s): gain %.3f est %.3f, offset %.2f est %.2f, depth error "
      "%.2f %%\n",
      exposure_known ? "known" : "unknown", gain, s_est, offset, r.affine_frame.b,
      100 * acc.median_rel_error);
  EXPECT_DOUBLE_EQ(r.exposure_ref, 1.0);
}

TEST(BrightnessChange, AffineBrightnessAbsorbsUnknownGainAndOffset) {
  runBrightnessChange(false);
}

TEST(BrightnessChange, KnownExposureLeavesAffineAtZero) {
  runBrightnessChange(true);
}

INSTANTIATE_TEST_SUITE_P(Motions, TranslatingCamera,
                         ::testing::Values(MotionCase{"sideways", {0.012, 0, 0}, 0.0},
                                           MotionCase{"sideways_turning", {-0.012, 0.002, 0}, 0.05},
                                           MotionCase{"forward", {0, 0, 0.03}, 0.0},
                                           MotionCase{"diagonal", {0.008, -0.004, 0.015}, -0.03}),
                         [](const ::testing::TestParamInfo<MotionCase>& p) {
                           return std::string(p.param.name);
                         });

}  // namespace
}  // namespace ldsm
