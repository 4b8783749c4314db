// Direct alignment of stored points to an image, on rendered planes with exact depths.
#include "alignment/direct_alignment.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <Eigen/Eigenvalues>

#include "image/interpolation.h"
#include "plane_scene.h"
#include "plane_scene_points.h"

namespace ldsm {
namespace {

using test::isometry;
using test::tangentPose;

constexpr int kW = 320, kH = 240;
constexpr double kF = 260.0, kCx = 159.5, kCy = 119.5;

struct Fixture {
  test::PlaneScene scene = test::PlaneScene::wallAndFloor(4.0);
  PyramidCamera camera{PinholeIntrinsics{kF, kF, kCx, kCy, kW, kH}, 3};
  std::vector<PatchPoint> points;
  ImagePyramid target{kW, kH, 3, false};

  /// Host at the origin, target at T_w_target; points on a grid of host pixels with gradient.
  void render(const SE3d& T_w_target, double brightness_scale, double brightness_offset) {
    ImageF idepth;
    const ImageF host =
        scene.render(Eigen::Isometry3d::Identity(), kF, kF, kCx, kCy, kW, kH, &idepth);
    ImageF tgt = scene.render(isometry(T_w_target), kF, kF, kCx, kCy, kW, kH);
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x)
        tgt(x, y) = static_cast<float>(brightness_scale * tgt(x, y) + brightness_offset);
    target.build(tgt.view());
    points = test::gridPatchPoints(host, idepth, 6, 8);
  }
};

TEST(DirectAlignment, RecoversAPoseWithRollAndBrightnessChangeFromAPerturbedStart) {
  Fixture f;
  const SE3d T_w_target = tangentPose(0.03, -0.05, 0.12, 0.25, -0.1, 0.3);
  f.render(T_w_target, 1.2, -10.0);
  ASSERT_GT(f.points.size(), 500u);
  const SE3d T_true = T_w_target.inverse();  // target <- host (host = world)
  const SE3d T_start = tangentPose(0.01, -0.008, 0.006, 0.03, 0.02, -0.03) * T_true;
  const DirectAlignmentResult r =
      alignPoints(f.points, f.camera, 0.f, f.target, T_start, 0.0, 0.0, DirectAlignmentSettings{});
  ASSERT_TRUE(r.success) << r.failure;
  const SE3d::Tangent err = (r.T_target_host * T_true.inverse()).log();
  EXPECT_LT(err.head<3>().norm(), 2e-3) << err.transpose();
  EXPECT_LT(err.tail<3>().norm(), 2e-4) << err.transpose();
  EXPECT_NEAR(std::exp(r.a), 1.2, 0.01);
  EXPECT_NEAR(r.b, -10.0, 1.0);
  EXPECT_GT(r.inliers, static_cast<int>(0.9 * r.in_image));
  // The information is positive definite.
  using Solver = Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>>;
  EXPECT_GT(Solver(r.information).eigenvalues().minCoeff(), 0.0);
  // The right scene's patterns correlate with the target's.
  EXPECT_GT(r.pattern_correlation, 0.9);
}

TEST(DirectAlignment, UnrelatedIntensitiesDoNotCorrelateWithTheTarget) {
  Fixture f;
  const SE3d T_w_target = tangentPose(0.0, 0.0, 0.0, 0.1, 0.0, 0.0);
  f.render(T_w_target, 1.0, 0.0);
  ASSERT_GT(f.points.size(), 500u);
  // The same geometry, but each point's pattern intensities are another point's.
  std::vector<PatchPoint> shuffled = f.points;
  std::mt19937 rng(7);
  for (std::size_t i = shuffled.size() - 1; i > 0; --i) {
    const std::size_t j = std::uniform_int_distribution<std::size_t>(0, i)(rng);
    std::swap(shuffled[i].colors, shuffled[j].colors);
  }
  const SE3d T_true = T_w_target.inverse();
  const DirectAlignmentResult right =
      alignPoints(f.points, f.camera, 0.f, f.target, T_true, 0.0, 0.0, DirectAlignmentSettings{});
  const DirectAlignmentResult wrong =
      alignPoints(shuffled, f.camera, 0.f, f.target, T_true, 0.0, 0.0, DirectAlignmentSettings{});
  EXPECT_GT(right.pattern_correlation, 0.9);
  EXPECT_LT(std::abs(wrong.pattern_correlation), 0.2) << "brightness scale " << std::exp(wrong.a);
}

}  // namespace
}  // namespace ldsm
