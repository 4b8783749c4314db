// Built-in scenes: names and errors, and the camera motion every scene promises: realistic
// speed and rotation per frame, smoothness, distance to surfaces, and the loop closing exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "ldsm/drivers/sim/det_math.h"
#include "ldsm/drivers/sim/sim_scene.h"
#include "ldsm/drivers/sim/sim_source.h"
#include "ldsm/error.h"
#include "sim_test_support.h"

namespace ldsm::drivers::sim {
namespace {

using test::sharedScene;

Pose poseAt(const SimScene& scene, double t) {
  const RigidPose r = evaluatePath(scene.path, t);
  const Quat q = quatFromMatrix(r.rotation);
  Pose p;
  p.rotation = Eigen::Quaterniond(q.w, q.x, q.y, q.z);
  p.translation = test::toEigen(r.translation);
  return p;
}

TEST(SimScene, NamesAndUnknownNames) {
  const auto names = simSceneNames();
  for (const char* n : {"loop", "loop2", "forward", "rotation", "short"})
    EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
  try {
    makeSimScene("corridor-of-doom");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("corridor-of-doom"), std::string::npos) << what;
    for (const auto& n : names) EXPECT_NE(what.find(n), std::string::npos) << what;
  }
  EXPECT_THROW(simSceneDescription("nope"), InputError);
  for (const auto& n : names) EXPECT_FALSE(simSceneDescription(n).empty());
}

TEST(SimScene, TooManyFramesForAnOpenPathIsAConfigError) {
  SimOptions o;
  o.frames = 100000;
  try {
    makeSimScene("forward", o);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("frames"), std::string::npos) << e.what();
  }
  // Closed paths can run for any number of frames.
  EXPECT_EQ(simFrameCount(*sharedScene("loop"), o), 100000);
  o.frames = 0;
  EXPECT_EQ(simFrameCount(*sharedScene("short"), o), 60);
}

TEST(SimScene, ScenesHaveTexturedQuadsAndLights) {
  for (const auto& name : simSceneNames()) {
    const auto scene = sharedScene(name);
    EXPECT_EQ(scene->name, name);
    EXPECT_GT(scene->quads.size(), 10u) << name;
    EXPECT_EQ(scene->details.size(), scene->quads.size()) << name;
    EXPECT_FALSE(scene->lights.empty()) << name;
    for (const SimQuad& q : scene->quads) {
      EXPECT_NEAR(norm(q.axis_u), 1.0, 1e-12);
      EXPECT_NEAR(norm(q.axis_v), 1.0, 1e-12);
      EXPECT_NEAR(dot(q.axis_u, q.axis_v), 0.0, 1e-12);
      EXPECT_GT(q.size_u, 0.0);
      EXPECT_GT(q.size_v, 0.0);
    }
  }
}

struct MotionStats {
  double max_step_m = 0, max_step_rad = 0, max_accel = 0, max_accel_jump = 0, max_angvel_jump = 0;
  double min_wall_distance = 1e9;
};

MotionStats motionStats(const SimScene& scene, double fps, std::int64_t frames) {
  MotionStats s;
  std::vector<Pose> poses;
  for (std::int64_t i = 0; i < frames; ++i) poses.push_back(poseAt(scene, i / fps));
  Eigen::Vector3d prev_accel = Eigen::Vector3d::Zero();
  double prev_angvel = -1;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const Eigen::Vector3d p = poses[i].translation;
    for (const SimQuad& q : scene.quads)
      s.min_wall_distance = std::min(s.min_wall_distance, test::distanceToQuad(q, p));
    if (i == 0) continue;
    s.max_step_m = std::max(s.max_step_m, (p - poses[i - 1].translation).norm());
    const double ang = test::rotationAngle(poses[i - 1], poses[i]);
    s.max_step_rad = std::max(s.max_step_rad, ang);
    if (prev_angvel >= 0)
      s.max_angvel_jump = std::max(s.max_angvel_jump, std::fabs(ang - prev_angvel) * fps * fps);
    prev_angvel = ang;
    if (i + 1 < poses.size()) {
      const Eigen::Vector3d a =
          (poses[i + 1].translation - 2 * p + poses[i - 1].translation) * fps * fps;
      s.max_accel = std::max(s.max_accel, a.norm());
      if (i > 1) s.max_accel_jump = std::max(s.max_accel_jump, (a - prev_accel).norm() * fps);
      prev_accel = a;
    }
  }
  return s;
}

TEST(SimScene, MotionIsSmoothSlowEnoughAndKeepsAwayFromSurfaces) {
  for (const auto& name : simSceneNames()) {
    const auto scene = sharedScene(name);
    const double fps = 30.0;
    const MotionStats s = motionStats(*scene, fps, simFrameCount(*scene, SimOptions{}));
    SCOPED_TRACE(name);
    EXPECT_LT(s.max_step_m, 0.05);                 // < 1.5 m/s
    EXPECT_LT(s.max_step_rad, 3.0 * kPi / 180.0);  // < 3 degrees per frame
    EXPECT_LT(s.max_accel, 3.0);                   // m/s^2
    EXPECT_LT(s.max_accel_jump, 20.0);             // m/s^3: acceleration is continuous
    EXPECT_LT(s.max_angvel_jump, 20.0);            // rad/s^2: angular velocity too
    EXPECT_GT(s.min_wall_distance, 0.5);           // no surface closer than 0.5 m
  }
}

TEST(SimScene, CamerasMoveAndRotateAsTheScenesDescribe) {
  const double fps = 30.0;
  const auto loop = motionStats(*sharedScene("loop"), fps, 300);
  EXPECT_GT(loop.max_step_m, 0.025);  // walking speed, about 1 m/s
  const auto rotation = motionStats(*sharedScene("rotation"), fps, 300);
  EXPECT_GT(rotation.max_step_rad, 1.5 * kPi / 180.0);  // strong panning
  EXPECT_LT(rotation.max_step_m, 0.01);                 // while moving slowly
}

TEST(SimScene, LoopReturnsExactlyToItsStartAndRevisitsIt) {
  const auto scene = sharedScene("loop");
  const double period = scene->path.period();
  ASSERT_GT(period, 40.0);
  SimOptions o;
  const std::int64_t frames = simFrameCount(*scene, o);
  const std::int64_t lap = static_cast<std::int64_t>(std::lround(period * o.fps));
  ASSERT_NEAR(lap / o.fps, period, 1e-12) << "a frame falls exactly on the lap";
  EXPECT_GT(frames, lap + 30) << "the sequence continues past the start";
  const Pose start = poseAt(*scene, 0.0), again = poseAt(*scene, lap / o.fps);
  EXPECT_LT((start.translation - again.translation).norm(), 1e-9);
  EXPECT_LT(test::rotationAngle(start, again), 1e-9);
  // In between it goes far away: a real loop, tens of metres long.
  double far = 0.0, length = 0.0;
  Pose prev = start;
  for (std::int64_t i = 1; i <= lap; ++i) {
    const Pose p = poseAt(*scene, i / o.fps);
    far = std::max(far, (p.translation - start.translation).norm());
    length += (p.translation - prev.translation).norm();
    prev = p;
  }
  EXPECT_GT(far, 10.0);
  EXPECT_GT(length, 40.0);
  EXPECT_LT(length, 60.0);
}

TEST(SimScene, TwoLapLoopDrivesTheSameLoopTwice) {
  const auto one = sharedScene("loop"), two = sharedScene("loop2");
  const double period = one->path.period();
  EXPECT_NEAR(two->path.period(), period, 1e-12);
  SimOptions o;
  const std::int64_t lap = static_cast<std::int64_t>(std::lround(period * o.fps));
  EXPECT_GT(simFrameCount(*two, o), 2 * lap) << "the default length covers both laps";
  EXPECT_LT(simFrameCount(*one, o), 2 * lap);
  for (std::int64_t i = 0; i <= lap; i += 97) {
    const Pose first = poseAt(*two, i / o.fps), second = poseAt(*two, (i + lap) / o.fps);
    EXPECT_LT((first.translation - second.translation).norm(), 1e-9) << i;
    EXPECT_LT(test::rotationAngle(first, second), 1e-9) << i;
    const Pose single = poseAt(*one, i / o.fps);
    EXPECT_LT((first.translation - single.translation).norm(), 1e-9) << i;
  }
}

TEST(SimScene, OpticalFlowPerFrameIsSmall) {
  // Median and 95th percentile flow of rendered pixels between consecutive frames, from the
  // rendered depth and the ground-truth poses, relative to the image width.
  SimOptions o;
  o.width = 160;
  o.height = 120;
  for (const auto& name : simSceneNames()) {
    SimSource src(sharedScene(name), o);
    const auto& gt = src.groundTruth();
    const auto& K = src.intrinsics();
    std::vector<double> flows;
    ImageF irr, invd;
    for (std::int64_t i = 0; i + 1 < src.frameCount();
         i += std::max<std::int64_t>(1, src.frameCount() / 12)) {
      src.renderer().renderIrradiance(gt[i].pose, irr, &invd);
      const Eigen::Isometry3d T_next_this =
          gt[i + 1].pose.isometry().inverse() * gt[i].pose.isometry();
      for (int y = 0; y < o.height; y += 4)
        for (int x = 0; x < o.width; x += 4) {
          const double w = invd(x, y);
          if (!(w > 0)) continue;
          const Eigen::Vector3d pc((x - K.cx) / K.fx / w, (y - K.cy) / K.fy / w, 1.0 / w);
          const Eigen::Vector3d q = T_next_this * pc;
          const double u = K.fx * q.x() / q.z() + K.cx, v = K.fy * q.y() / q.z() + K.cy;
          flows.push_back(std::hypot(u - x, v - y) / o.width);
        }
    }
    ASSERT_GT(flows.size(), 1000u);
    std::sort(flows.begin(), flows.end());
    SCOPED_TRACE(name);
    EXPECT_LT(flows[flows.size() / 2], 0.02);
    EXPECT_LT(flows[flows.size() * 95 / 100], 0.05);
  }
}

}  // namespace
}  // namespace ldsm::drivers::sim
