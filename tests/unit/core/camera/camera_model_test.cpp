#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "camera/camera_models.h"
#include "ldsm/camera/camera_model.h"
#include "ldsm/error.h"
#include "sample_cameras.h"

namespace ldsm {
namespace {

using test::allSampleCameras;

TEST(CameraModel, FactoryBuildsTheRequestedModel) {
  for (const auto& c : allSampleCameras()) {
    const auto cam = makeCameraModel(c.intrinsics);
    EXPECT_EQ(cam->type(), c.intrinsics.model) << c.name;
    EXPECT_EQ(cam->clone()->type(), c.intrinsics.model) << c.name;
    EXPECT_EQ(cam->numParameters(), 4 + numDistortionParameters(c.intrinsics.model));
    EXPECT_EQ(cam->parameters()[2], c.intrinsics.cx);
  }
}

// Every pixel on a grid unprojects to a unit ray that projects back to the same pixel.
TEST(CameraModel, UnprojectProjectRoundTripOverTheImage) {
  for (const auto& c : allSampleCameras()) {
    const auto cam = makeCameraModel(c.intrinsics);
    int checked = 0;
    for (double v = 0; v <= cam->height() - 1; v += 7.5) {
      for (double u = 0; u <= cam->width() - 1; u += 7.5) {
        const Eigen::Vector2d px(u, v);
        Eigen::Vector3d ray;
        ASSERT_TRUE(cam->unproject(px, &ray)) << c.name << " at " << px.transpose();
        EXPECT_NEAR(ray.norm(), 1.0, 1e-12);
        for (const double depth : {0.3, 7.0}) {
          Eigen::Vector2d back;
          ASSERT_TRUE(cam->project(depth * ray, &back)) << c.name << " at " << px.transpose();
          EXPECT_LT((back - px).norm(), 1e-6) << c.name << " at " << px.transpose();
        }
        ++checked;
      }
    }
    EXPECT_GT(checked, 1000);
  }
}

// 3D points that project into the image unproject to their own direction.
TEST(CameraModel, ProjectUnprojectRoundTripFromPoints) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> dir(-1.5, 1.5), depth(0.5, 20.0);
  for (const auto& c : allSampleCameras()) {
    const auto cam = makeCameraModel(c.intrinsics);
    int inside = 0;
    for (int i = 0; i < 3000; ++i) {
      const Eigen::Vector3d p = depth(rng) * Eigen::Vector3d(dir(rng), dir(rng), 1.0).normalized();
      Eigen::Vector2d px;
      if (!cam->project(p, &px) || !cam->inImage(px)) continue;
      ++inside;
      Eigen::Vector3d ray;
      ASSERT_TRUE(cam->unproject(px, &ray)) << c.name;
      EXPECT_LT((ray - p.normalized()).norm(), 1e-9) << c.name;
    }
    EXPECT_GT(inside, 300) << c.name;
  }
}

TEST(CameraModel, FisheyeSeesBeyondNinetyDegrees) {
  const auto cam = makeCameraModel(test::equidistantIntrinsics());
  Eigen::Vector3d ray;
  ASSERT_TRUE(cam->unproject({0.0, 0.0}, &ray));  // image corner, about 109 degrees off-axis
  EXPECT_LT(ray.z(), 0.0);
  Eigen::Vector2d px;
  ASSERT_TRUE(cam->project(ray, &px));
  EXPECT_LT(px.norm(), 1e-6);
  EXPECT_FALSE(cam->project({0.0, 0.0, -1.0}, &px));  // straight behind
}

TEST(CameraModel, RejectsPointsBehindTheCamera) {
  for (const auto& c : allSampleCameras()) {
    if (c.intrinsics.model == CameraModelType::Equidistant) continue;
    const auto cam = makeCameraModel(c.intrinsics);
    Eigen::Vector2d px(-5, -5);
    EXPECT_FALSE(cam->project({0.1, 0.2, -1.0}, &px)) << c.name;
    EXPECT_FALSE(cam->project({0.1, 0.2, 0.0}, &px)) << c.name;
    EXPECT_EQ(px, Eigen::Vector2d(-5, -5)) << c.name;  // untouched on failure
    CameraModel::IntrinsicsJacobian J;
    EXPECT_FALSE(cam->intrinsicsJacobian({0.1, 0.2, -1.0}, &J)) << c.name;
  }
}

TEST(CameraModel, RadTanRejectsPointsBeyondTheInvertibleRadius) {
  // 1 + 3 k1 r^2 = 0 at r^2 = 2/3 for k1 = -0.5.
  const auto in = test::makeIntrinsics(CameraModelType::RadTan, 300, 300, 320, 240,
                                       {-0.5, 0.0, 0.0, 0.0}, 640, 480);
  RadTanCamera cam(in);
  EXPECT_NEAR(cam.maxRadiusSquared(), 2.0 / 3.0, 1e-12);
  Eigen::Vector2d px;
  EXPECT_TRUE(cam.project({0.8, 0.0, 1.0}, &px));
  EXPECT_FALSE(cam.project({0.9, 0.0, 1.0}, &px));
  // The largest distorted radius is reached at the limit; beyond it nothing unprojects.
  const double r = std::sqrt(2.0 / 3.0), rd = r * (1 - 0.5 * r * r);
  Eigen::Vector3d ray;
  EXPECT_TRUE(cam.unproject({320 + 300 * rd * 0.99, 240}, &ray));
  EXPECT_FALSE(cam.unproject({320 + 300 * rd * 1.01, 240}, &ray));
}

TEST(CameraModel, PointJacobianMatchesNumericDifferentiation) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> dir(-1.2, 1.2), depth(0.5, 10.0);
  for (const auto& c : allSampleCameras()) {
    const auto cam = makeCameraModel(c.intrinsics);
    std::vector<Eigen::Vector3d> points = {{0, 0, 2}, {1e-13, -1e-13, 1}};  // on the axis
    for (int i = 0; i < 300; ++i)
      points.push_back(depth(rng) * Eigen::Vector3d(dir(rng), dir(rng), 1.0).normalized());
    for (const auto& p : points) {
      Eigen::Vector2d px;
      CameraModel::PointJacobian J;
      if (!cam->project(p, &px, &J)) continue;
      const double h = 1e-6 * p.norm();
      for (int k = 0; k < 3; ++k) {
        Eigen::Vector3d dp = Eigen::Vector3d::Zero();
        dp[k] = h;
        Eigen::Vector2d plus, minus;
        ASSERT_TRUE(cam->project(p + dp, &plus) && cam->project(p - dp, &minus));
        const Eigen::Vector2d numeric = (plus - minus) / (2 * h);
        EXPECT_LT((J.col(k) - numeric).norm(), 1e-5 * (1.0 + numeric.norm()))
            << c.name << " p=" << p.transpose() << " k=" << k << " analytic "
            << J.col(k).transpose() << " numeric " << numeric.transpose();
      }
    }
  }
}

TEST(CameraModel, IntrinsicsJacobianMatchesNumericDifferentiation) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> dir(-1.0, 1.0), depth(0.5, 10.0);
  for (const auto& c : allSampleCameras()) {
    const auto cam = makeCameraModel(c.intrinsics);
    const Eigen::VectorXd params = cam->parameters();
    std::vector<Eigen::Vector3d> points = {{0, 0, 3}};
    for (int i = 0; i < 100; ++i)
      points.push_back(depth(rng) * Eigen::Vector3d(dir(rng), dir(rng), 1.0).normalized());
    for (const auto& p : points) {
      CameraModel::IntrinsicsJacobian J;
      Eigen::Vector2d px;
      if (!cam->project(p, &px)) continue;
      ASSERT_TRUE(cam->intrinsicsJacobian(p, &J)) << c.name;
      ASSERT_EQ(J.cols(), cam->numParameters());
      for (int k = 0; k < cam->numParameters(); ++k) {
        // omega must stay >= 0: second-order one-sided difference at omega = 0.
        const bool one_sided = params[k] == 0.0 && c.intrinsics.model == CameraModelType::Fov;
        const double h = 1e-6 * std::max(1.0, std::abs(params[k]));
        const auto projectWith = [&](double delta) {
          Eigen::VectorXd q = params;
          q[k] += delta;
          Eigen::Vector2d out;
          EXPECT_TRUE(cam->withParameters(q)->project(p, &out));
          return out;
        };
        const Eigen::Vector2d numeric =
            one_sided
                ? Eigen::Vector2d(
                      (-3.0 * projectWith(0) + 4.0 * projectWith(h) - projectWith(2 * h)) / (2 * h))
                : Eigen::Vector2d((projectWith(h) - projectWith(-h)) / (2 * h));
        EXPECT_LT((J.col(k) - numeric).norm(), 1e-4 * (1.0 + numeric.norm()))
            << c.name << " param " << k << " analytic " << J.col(k).transpose() << " numeric "
            << numeric.transpose();
      }
    }
  }
}

TEST(CameraModel, FovWithZeroOmegaIsAPinhole) {
  const auto fov = makeCameraModel(
      test::makeIntrinsics(CameraModelType::Fov, 300, 310, 320, 240, {0.0}, 640, 480));
  const auto pin = makeCameraModel(
      test::makeIntrinsics(CameraModelType::Pinhole, 300, 310, 320, 240, {}, 640, 480));
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(0.3, -0.2, 1.0), Eigen::Vector3d(-2, 1, 3)}) {
    Eigen::Vector2d a, b;
    ASSERT_TRUE(fov->project(p, &a) && pin->project(p, &b));
    EXPECT_LT((a - b).norm(), 1e-9);
  }
}

TEST(CameraModel, FovMatchesTheClosedForm) {
  // rd = atan(2 r tan(omega/2)) / omega for r = 0.5, omega = 0.9.
  const auto cam = makeCameraModel(test::fovIntrinsics());
  Eigen::Vector2d px;
  ASSERT_TRUE(cam->project({0.5, 0.0, 1.0}, &px));
  const double rd = std::atan(2 * 0.5 * std::tan(0.45)) / 0.9;
  EXPECT_NEAR(px.x(), 300 * rd + 319.5, 1e-9);
  EXPECT_NEAR(px.y(), 239.5, 1e-12);
}

TEST(CameraModel, RadTanMatchesTheOpenCvFormula) {
  const auto in = test::pincushionIntrinsics();
  const auto cam = makeCameraModel(in);
  const double x = 0.3, y = -0.2, r2 = x * x + y * y;
  const auto& d = in.distortion;
  const double radial = 1 + d[0] * r2 + d[1] * r2 * r2;
  const double xd = x * radial + 2 * d[2] * x * y + d[3] * (r2 + 2 * x * x);
  const double yd = y * radial + d[2] * (r2 + 2 * y * y) + 2 * d[3] * x * y;
  Eigen::Vector2d px;
  ASSERT_TRUE(cam->project({2 * x, 2 * y, 2.0}, &px));
  EXPECT_NEAR(px.x(), in.fx * xd + in.cx, 1e-9);
  EXPECT_NEAR(px.y(), in.fy * yd + in.cy, 1e-9);
}

TEST(CameraModel, EquidistantMatchesTheOpenCvFisheyeFormula) {
  const auto in = test::equidistantIntrinsics();
  const auto cam = makeCameraModel(in);
  const Eigen::Vector3d p(0.4, 0.7, 1.1);
  const double a = p.x() / p.z(), b = p.y() / p.z(), r = std::hypot(a, b);
  const double t = std::atan(r), t2 = t * t;
  const auto& k = in.distortion;
  const double td =
      t * (1 + k[0] * t2 + k[1] * t2 * t2 + k[2] * t2 * t2 * t2 + k[3] * t2 * t2 * t2 * t2);
  Eigen::Vector2d px;
  ASSERT_TRUE(cam->project(p, &px));
  EXPECT_NEAR(px.x(), in.fx * td / r * a + in.cx, 1e-9);
  EXPECT_NEAR(px.y(), in.fy * td / r * b + in.cy, 1e-9);
}

void expectInvalid(CameraIntrinsics in, const std::string& field) {
  try {
    makeCameraModel(in);
    ADD_FAILURE() << "accepted invalid intrinsics (" << field << ")";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
  }
}

TEST(CameraModel, ValidationNamesTheBadField) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  auto in = test::radTanIntrinsics();
  in.fx = nan;
  expectInvalid(in, "fx");
  in = test::radTanIntrinsics();
  in.fy = 0.0;
  expectInvalid(in, "fy");
  in = test::radTanIntrinsics();
  in.fx = -3.0;
  expectInvalid(in, "fx");
  in = test::radTanIntrinsics();
  in.cy = inf;
  expectInvalid(in, "cy");
  in = test::radTanIntrinsics();
  in.distortion[2] = nan;
  expectInvalid(in, "p1");
  in = test::radTanIntrinsics();
  in.width = 0;
  expectInvalid(in, "size");
  in = test::radTanIntrinsics();
  in.height = -4;
  expectInvalid(in, "size");
  in = test::radTanIntrinsics();
  in.distortion.pop_back();
  expectInvalid(in, "distortion parameters");
  in = test::fovIntrinsics();
  in.distortion[0] = 3.5;
  expectInvalid(in, "omega");
  in = test::fovIntrinsics();
  in.distortion[0] = -0.1;
  expectInvalid(in, "omega");
  in = test::pinholeIntrinsics();
  in.distortion = {0.1};
  expectInvalid(in, "distortion parameters");
  // A model of the wrong type for the class.
  EXPECT_THROW(PinholeCamera(test::fovIntrinsics()), InputError);
  // withParameters validates too.
  const auto cam = makeCameraModel(test::pinholeIntrinsics());
  EXPECT_THROW(cam->withParameters(Eigen::Vector4d(0, 1, 2, 3)), InputError);
  EXPECT_THROW(cam->withParameters(Eigen::Vector3d(1, 2, 3)), InputError);
}

}  // namespace
}  // namespace ldsm
