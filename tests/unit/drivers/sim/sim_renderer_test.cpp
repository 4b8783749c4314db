// The renderer against an independent ray caster: depth, texture lookup, brightness constancy
// between frames, anti-aliasing, supersampling, and error handling.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "ldsm/drivers/sim/sim_renderer.h"
#include "ldsm/drivers/sim/sim_source.h"
#include "ldsm/error.h"
#include "sim_test_support.h"

namespace ldsm::drivers::sim {
namespace {

using test::sharedScene;

PinholeIntrinsics camera(int w, int h, double f) {
  PinholeIntrinsics c;
  c.fx = c.fy = f;
  c.cx = 0.5 * (w - 1);
  c.cy = 0.5 * (h - 1);
  c.width = w;
  c.height = h;
  return c;
}

Eigen::Vector3d rayDirection(const PinholeIntrinsics& c, const Pose& pose, double x, double y) {
  return pose.rotation.normalized() * Eigen::Vector3d((x - c.cx) / c.fx, (y - c.cy) / c.fy, 1.0);
}

TEST(SimRenderer, InverseDepthMatchesAnIndependentRayCaster) {
  for (const char* name : {"short", "loop"}) {
    const auto scene = sharedScene(name);
    const PinholeIntrinsics cam = camera(96, 72, 60.0);
    RenderSettings settings;
    settings.antialias_edges = false;
    SimRenderer renderer(scene, cam, settings);
    SimOptions o;
    SimSource src(scene, o);
    int checked = 0;
    for (std::int64_t f : {0, 17, 45}) {
      const Pose pose = src.groundTruth()[static_cast<std::size_t>(f)].pose;
      ImageF irr, invd;
      renderer.renderIrradiance(pose, irr, &invd);
      for (int y = 0; y < cam.height; y += 3)
        for (int x = 0; x < cam.width; x += 3) {
          const test::RayHit hit =
              test::castRay(*scene, pose.translation, rayDirection(cam, pose, x, y));
          if (hit.quad < 0 || hit.edge_distance < 0.01) continue;  // ambiguous at borders
          ASSERT_GT(invd(x, y), 0.0f);
          EXPECT_NEAR(invd(x, y) * hit.s, 1.0, 2e-4)
              << name << " frame " << f << " at " << x << "," << y;
          EXPECT_EQ(renderer.lastQuadIds()(x, y), hit.quad);
          ++checked;
        }
    }
    EXPECT_GT(checked, 1000) << name;
  }
}

TEST(SimRenderer, MagnifiedTexturesMatchTheReferenceIrradiance) {
  // A narrow field of view makes every texel span several pixels, so the renderer reads level 0
  // of both textures: its value must equal the scene's reference lookup at the ray's hit point.
  const auto scene = sharedScene("short");
  const PinholeIntrinsics cam = camera(80, 60, 2500.0);
  RenderSettings settings;
  settings.antialias_edges = false;
  SimRenderer renderer(scene, cam, settings);
  SimSource src(scene, SimOptions{});
  int checked = 0;
  for (std::size_t f : {0u, 30u}) {
    const Pose pose = src.groundTruth()[f].pose;
    ImageF irr;
    renderer.renderIrradiance(pose, irr);
    for (int y = 1; y < cam.height - 1; y += 2)
      for (int x = 1; x < cam.width - 1; x += 2) {
        const test::RayHit hit =
            test::castRay(*scene, pose.translation, rayDirection(cam, pose, x, y));
        const test::RayHit hx =
            test::castRay(*scene, pose.translation, rayDirection(cam, pose, x + 1, y));
        const test::RayHit hy =
            test::castRay(*scene, pose.translation, rayDirection(cam, pose, x, y + 1));
        if (hit.quad < 0 || hit.quad != hx.quad || hit.quad != hy.quad || hit.edge_distance < 0.01)
          continue;
        // Footprint (metres per pixel) by numeric differentiation: only magnified pixels.
        const double fp = std::max(std::hypot(hx.u - hit.u, hx.v - hit.v),
                                   std::hypot(hy.u - hit.u, hy.v - hit.v));
        if (fp > 0.8 * 0.005) continue;
        const double ref = scene->irradianceAt(hit.quad, hit.u, hit.v);
        EXPECT_NEAR(irr(x, y), ref, 2e-3 * std::max(1.0, ref)) << "at " << x << "," << y;
        ++checked;
      }
  }
  EXPECT_GT(checked, 500);
}

TEST(SimRenderer, BrightnessIsConstantAlongGroundTruthMotion) {
  // Reprojecting frame i into frame i+2 with the rendered depth and the ground-truth poses lands
  // on the same irradiance (the renderer and the trajectory agree).
  const auto scene = sharedScene("loop");
  const PinholeIntrinsics cam = camera(320, 240, 190.0);
  SimRenderer renderer(scene, cam);
  SimSource src(scene, SimOptions{});
  std::vector<double> err, base;
  for (std::size_t f : {10u, 400u, 900u}) {
    const Pose a = src.groundTruth()[f].pose, b = src.groundTruth()[f + 2].pose;
    ImageF ia, da, ib, db;
    renderer.renderIrradiance(a, ia, &da);
    renderer.renderIrradiance(b, ib, &db);
    const Eigen::Isometry3d T_ba = b.isometry().inverse() * a.isometry();
    for (int y = 2; y < cam.height - 2; y += 3)
      for (int x = 2; x < cam.width - 2; x += 3) {
        const double w = da(x, y);
        if (!(w > 0)) continue;
        const Eigen::Vector3d q =
            T_ba * Eigen::Vector3d((x - cam.cx) / cam.fx / w, (y - cam.cy) / cam.fy / w, 1.0 / w);
        const double u = cam.fx * q.x() / q.z() + cam.cx, v = cam.fy * q.y() / q.z() + cam.cy;
        const int iu = static_cast<int>(std::lround(u)), iv = static_cast<int>(std::lround(v));
        if (iu < 1 || iv < 1 || iu >= cam.width - 1 || iv >= cam.height - 1) continue;
        if (std::fabs(db(iu, iv) * q.z() - 1.0) > 0.01) continue;  // occluded
        const int i0 = static_cast<int>(u), j0 = static_cast<int>(v);
        const double fu = u - i0, fv = v - j0;
        const double vb = (1 - fv) * ((1 - fu) * ib(i0, j0) + fu * ib(i0 + 1, j0)) +
                          fv * ((1 - fu) * ib(i0, j0 + 1) + fu * ib(i0 + 1, j0 + 1));
        err.push_back(std::fabs(ia(x, y) - vb));
        base.push_back(std::fabs(ia(x, y) - ib(x, y)));  // same pixel, no motion compensation
      }
  }
  ASSERT_GT(err.size(), 3000u);
  std::sort(err.begin(), err.end());
  std::sort(base.begin(), base.end());
  const double med_err = err[err.size() / 2], med_base = base[base.size() / 2];
  EXPECT_LT(med_err, 0.2 * med_base) << "median " << med_err << " vs " << med_base;
  EXPECT_LT(med_err, 0.01);
}

// A scene of flat-coloured quads: a wall, a floor and a pillar, so that only geometric edges
// (not texture filtering) make images differ.
std::shared_ptr<const SimScene> flatScene() {
  SimScene s;
  s.name = "flat";
  for (float albedo : {0.2f, 0.5f, 0.9f})
    s.textures.push_back(buildMipTexture(ImageF(1, 1, albedo), true, 0.01));
  auto quad = [&](Vec3 o, Vec3 u, Vec3 v, double su, double sv, int tex) {
    SimQuad q;
    q.origin = o;
    q.axis_u = u;
    q.axis_v = v;
    q.size_u = su;
    q.size_v = sv;
    q.texture = tex;
    s.quads.push_back(q);
  };
  quad({6, -5, -1}, {0, 1, 0}, {0, 0, 1}, 10, 5, 0);    // wall
  quad({0, -5, 0}, {1, 0, 0}, {0, 1, 0}, 6, 10, 1);     // floor
  quad({3, -0.3, 0}, {0, 1, 0}, {0, 0, 1}, 0.6, 3, 2);  // pillar front
  return std::make_shared<const SimScene>(std::move(s));
}

TEST(SimRenderer, EdgeAntiAliasingApproachesSupersampling) {
  // Against a 4x4 supersampled reference, edge pixels rendered with 4 sub-samples are much closer
  // than single-sample ones.
  const auto scene = flatScene();
  const PinholeIntrinsics cam = camera(160, 120, 120.0);
  RenderSettings ref_s, aa_s, none_s;
  ref_s.supersampling = 4;
  none_s.antialias_edges = false;
  SimRenderer ref_r(scene, cam, ref_s), aa_r(scene, cam, aa_s), none_r(scene, cam, none_s);
  double err_aa = 0, err_none = 0;
  int edges = 0;
  for (double roll : {0.1, 0.35, -0.6}) {
    // Looking along +x from 1.5 m height, rolled about the optical axis.
    Pose pose;
    pose.translation = Eigen::Vector3d(0.0, 0.1, 1.5);
    Eigen::Matrix3d R;
    R.col(0) = Eigen::Vector3d(0, -1, 0);
    R.col(1) = Eigen::Vector3d(0, 0, -1);
    R.col(2) = Eigen::Vector3d(1, 0, 0);
    pose.rotation = Eigen::Quaterniond(R * Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()));
    ImageF ref, aa, none;
    ref_r.renderIrradiance(pose, ref);
    aa_r.renderIrradiance(pose, aa);
    none_r.renderIrradiance(pose, none);
    for (int y = 0; y < cam.height; ++y)
      for (int x = 0; x < cam.width; ++x) {
        if (std::fabs(none(x, y) - ref(x, y)) < 1e-6 && std::fabs(aa(x, y) - ref(x, y)) < 1e-6)
          continue;
        err_aa += std::fabs(aa(x, y) - ref(x, y));
        err_none += std::fabs(none(x, y) - ref(x, y));
        ++edges;
      }
  }
  ASSERT_GT(edges, 300);
  EXPECT_LT(err_aa, 0.5 * err_none) << "aa " << err_aa / edges << " none " << err_none / edges;
}

TEST(SimRenderer, SupersamplingKeepsTheImageAndDepth) {
  const auto scene = sharedScene("short");
  const PinholeIntrinsics cam = camera(64, 48, 40.0);
  RenderSettings s2;
  s2.supersampling = 2;
  SimRenderer r1(scene, cam), r2(scene, cam, s2);
  const Pose pose = SimSource(scene, SimOptions{}).groundTruth()[5].pose;
  ImageF a, b, da, db;
  r1.renderIrradiance(pose, a, &da);
  r2.renderIrradiance(pose, b, &db);
  ASSERT_EQ(b.width(), 64);
  ASSERT_EQ(b.height(), 48);
  EXPECT_EQ(r2.lastQuadIds().width(), 128);
  double diff = 0, mean = 0;
  int depth_off = 0;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) {
      diff += std::fabs(a(x, y) - b(x, y));
      mean += a(x, y);
      // The mean inverse depth of the sub-samples equals the centre's on a plane; only pixels on
      // depth edges differ.
      depth_off += std::fabs(db(x, y) - da(x, y)) > 1e-4 * da(x, y);
    }
  EXPECT_LT(diff, 0.1 * mean);
  EXPECT_LT(depth_off, 48 * 64 / 20);
}

TEST(SimRenderer, RejectsBadCamerasAndSettings) {
  const auto scene = sharedScene("short");
  EXPECT_THROW(SimRenderer(scene, camera(64, 48, 0.0)), ConfigError);
  EXPECT_THROW(SimRenderer(scene, camera(0, 48, 40.0)), ConfigError);
  RenderSettings s;
  s.supersampling = 5;
  EXPECT_THROW(SimRenderer(scene, camera(64, 48, 40.0), s), ConfigError);
  EXPECT_THROW(SimRenderer(nullptr, camera(64, 48, 40.0)), ConfigError);
  SimScene broken = *scene;
  broken.quads[0].texture = 99;
  EXPECT_THROW(SimRenderer(std::make_shared<const SimScene>(broken), camera(64, 48, 40.0)),
               InputError);
}

TEST(SimRenderer, ViewFromOutsideTheSceneIsBlackNotGarbage) {
  const auto scene = sharedScene("short");
  SimRenderer r(scene, camera(32, 24, 20.0));
  Pose pose;
  pose.translation = Eigen::Vector3d(0, 0, 100.0);  // high above, looking up (+z)
  ImageF irr, invd;
  r.renderIrradiance(pose, irr, &invd);
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 32; ++x) {
      EXPECT_EQ(irr(x, y), 0.0f);
      EXPECT_EQ(invd(x, y), 0.0f);
    }
}

}  // namespace
}  // namespace ldsm::drivers::sim
