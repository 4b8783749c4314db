// The Mapper on a small synthetic window (rendered planes, a perfect initialisation): keyframes
// are optimised onto the truth, the window stays within its bounds by marginalising keyframes,
// and everything the map keeps leaves as values (MapUpdate).
#include "backend/mapper.h"
#include "pipeline/stage_settings.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <set>

#include "synthetic_window.h"

namespace ldsm {
namespace {

using test::poseError;
using test::SyntheticWindow;

Config mapperConfig() {
  Config c;
  c.calibration.refine_radial = false;
  c.calibration.refine_focal = false;
  c.calibration.refine_principal_point = false;
  return c;
}

MapperFrame frameInfo(const SyntheticWindow& /*w*/, int i, const SE3d& T_c_w) {
  return {i, 0.1 * i, 1.0, T_c_w, AffineLight{}};
}

/// A start 5.4 mrad off the truth in rotation, as tracking might give.
SE3d perturbed(const SE3d& T) {
  SE3d::Tangent d;
  d << 0.0, 0.0, 0.0, 0.003, -0.004, 0.002;
  return SE3d::exp(d) * T;
}

void expectConvergesToTheTruthAndStaysBounded(bool keyframe_images_16bit) {
  SyntheticWindow w(30);
  Config config = mapperConfig();
  config.window.keyframe_images_16bit = keyframe_images_16bit;
  Mapper mapper(mapperSettings(config, false), w.camera(), w.pool());
  KeyframeInsertion init;
  ASSERT_TRUE(mapper.initialize(w.initialization(2), frameInfo(w, 0, w.T_c_w(0)), w.pyramid(0),
                                frameInfo(w, 2, w.T_c_w(2)), w.pyramid(2), &init));
  EXPECT_TRUE(mapper.initialized());
  EXPECT_GT(mapper.activePointCount(), 500);
  ASSERT_EQ(init.map.keyframes.size(), 2u);  // both keyframes' poses for the map

  std::set<int> left_ids;
  std::size_t points_out = 0;
  for (int i = 3; i < w.frames(); ++i) {
    if (i % 3 != 0) {
      mapper.traceFrame(*w.pyramid(i), frameInfo(w, i, w.T_c_w(i)));
      continue;
    }
    const KeyframeInsertion ins =
        mapper.addKeyframe(w.pyramid(i), frameInfo(w, i, perturbed(w.T_c_w(i))));
    // The rotation error of the start is removed, the position stays within a few millimetres
    // over the 1 m path (measured: 0.2-1.2 mrad, 3.2-5.4 mm).
    const Eigen::Vector2d err = poseError(mapper.newestKeyframe().T_c_w, w.T_c_w(i));
    EXPECT_LT(err.x(), 2.5e-3) << "keyframe of frame " << i;
    EXPECT_LT(err.y(), 0.01) << "keyframe of frame " << i;
    EXPECT_LE(mapper.windowPoses().size(), static_cast<std::size_t>(config.window.max_keyframes));
    for (const MarginalizedKeyframe& kf : ins.map.left) {
      EXPECT_TRUE(left_ids.insert(kf.id).second) << "keyframe " << kf.id << " left twice";
      EXPECT_FALSE(kf.points.empty());
      // Without loop closure a leaving keyframe is not described (no corners, no image).
      EXPECT_TRUE(kf.image.empty());
    }
    // Every pose handed on is finite; the window's own come last.
    ASSERT_GE(ins.map.keyframes.size(), mapper.windowPoses().size());
    for (const KeyframeRecord& r : ins.map.keyframes) EXPECT_TRUE(r.T_w_c.matrix().allFinite());
    points_out += ins.map.points.size();
  }
  EXPECT_GE(left_ids.size(), 2u) << "the window never marginalised a keyframe";
  EXPECT_GT(points_out, 0u);
  // Only the newest keyframe keeps its whole pyramid; the older ones keep the level-0
  // intensities their residuals sample (ImagePyramid::compact: 4 bytes per pixel).
  const std::size_t full = w.pyramid(0)->bytes();
  // In 16 bits: 2 bytes per pixel (window.keyframe_images_16bit).
  const std::size_t level0 = keyframe_images_16bit
                                 ? sizeof(std::int16_t) * SyntheticWindow::kW * SyntheticWindow::kH
                                 : sizeof(float) * SyntheticWindow::kW * SyntheticWindow::kH;
  const std::size_t n = mapper.windowPoses().size();
  EXPECT_EQ(mapper.windowImageBytes(), full + (n - 1) * level0);
  // Once the tracking reference is made from the newest, it needs no more either.
  mapper.compactNewestImage();
  EXPECT_EQ(mapper.windowImageBytes(), n * level0);
  // The reference for tracking is the newest keyframe, with its pyramid (whole until
  // compactNewestImage()).
  const TrackingReference ref = mapper.newestReference();
  EXPECT_EQ(ref.keyframe_id, mapper.newestKeyframe().id());
  ASSERT_NE(ref.pyramid, nullptr);
  std::vector<DepthPoint> depth;
  mapper.trackingPoints(depth);
  EXPECT_GT(depth.size(), 300u);
  for (const DepthPoint& p : depth) {
    EXPECT_GT(p.idepth, 0.f);
    EXPECT_GE(p.u, 0.f);
    EXPECT_LE(p.u, SyntheticWindow::kW - 1.f);
  }
}

TEST(Mapper, KeyframesConvergeToTheTruthAndTheWindowStaysBounded) {
  expectConvergesToTheTruthAndStaysBounded(false);
}

// The same bounds when the older keyframes keep their level 0 in 16 bits.
TEST(Mapper, KeyframesWithSixteenBitImagesConvergeToTheTruthAndTheWindowStaysBounded) {
  expectConvergesToTheTruthAndStaysBounded(true);
}

TEST(Mapper, ALeavingKeyframesPyramidGoesBackToThePoolOnlyOnceTheNewestIsCompacted) {
  // The pool makes a leaving keyframe's compacted pyramid whole again: were that done while the
  // newest keyframe still holds its whole pyramid, two whole pyramids would be held at once.
  SyntheticWindow w(30);
  Mapper mapper(mapperSettings(mapperConfig(), false), w.camera(), w.pool());
  ASSERT_TRUE(mapper.initialize(w.initialization(2), frameInfo(w, 0, w.T_c_w(0)), w.pyramid(0),
                                frameInfo(w, 2, w.T_c_w(2)), w.pyramid(2), nullptr));
  mapper.compactNewestImage();
  int left = 0;
  for (int i = 3; i < w.frames() && left == 0; i += 3) {
    ASSERT_EQ(w.pool().freeCount(), 0u) << "the frames here take every pyramid the pool has";
    const KeyframeInsertion ins = mapper.addKeyframe(w.pyramid(i), frameInfo(w, i, w.T_c_w(i)));
    left = static_cast<int>(ins.map.left.size());
    EXPECT_EQ(w.pool().freeCount(), 0u) << "keyframe of frame " << i;
    mapper.compactNewestImage();
    // Back in the pool (which keeps one spare) once the newest is compacted.
    EXPECT_EQ(w.pool().freeCount(), left > 0 ? 1u : 0u) << "keyframe of frame " << i;
    if (left == 0) continue;
    // Taken by the next frame, as tracking would.
    std::unique_ptr<ImagePyramid> next = w.pool().acquire();
    EXPECT_EQ(next->bytes(), w.pyramid(0)->bytes()) << "a whole pyramid again";
  }
  EXPECT_GT(left, 0) << "no keyframe left the window";
}

TEST(Mapper, ParallelTracingAndLinearisationGiveTheSameWindowBitForBit) {
  // system.parallel_threads: tracing one task per keyframe, linearising one per host keyframe.
  SyntheticWindow w(24);
  const Config config = mapperConfig();
  const auto run = [&](concurrency::ParallelTasks* tasks) {
    Mapper mapper(mapperSettings(config, false), w.camera(), w.pool());
    mapper.setParallelTasks(tasks);
    KeyframeInsertion init;
    EXPECT_TRUE(mapper.initialize(w.initialization(2), frameInfo(w, 0, w.T_c_w(0)), w.pyramid(0),
                                  frameInfo(w, 2, w.T_c_w(2)), w.pyramid(2), &init));
    for (int i = 3; i < w.frames(); ++i) {
      if (i % 3 != 0)
        mapper.traceFrame(*w.pyramid(i), frameInfo(w, i, w.T_c_w(i)));
      else
        mapper.addKeyframe(w.pyramid(i), frameInfo(w, i, perturbed(w.T_c_w(i))));
    }
    std::vector<DepthPoint> depth;
    mapper.trackingPoints(depth);
    return std::make_pair(mapper.windowPoses(), depth);
  };
  const auto serial = run(nullptr);
  concurrency::ParallelTasks tasks(2);
  const auto parallel = run(&tasks);
  ASSERT_EQ(parallel.first.size(), serial.first.size());
  for (std::size_t k = 0; k < serial.first.size(); ++k)
    EXPECT_EQ(parallel.first[k].T_w_c.matrix(), serial.first[k].T_w_c.matrix()) << k;
  ASSERT_EQ(parallel.second.size(), serial.second.size());
  ASSERT_GT(serial.second.size(), 300u);
  for (std::size_t i = 0; i < serial.second.size(); ++i) {
    ASSERT_EQ(parallel.second[i].u, serial.second[i].u) << i;
    ASSERT_EQ(parallel.second[i].v, serial.second[i].v) << i;
    ASSERT_EQ(parallel.second[i].idepth, serial.second[i].idepth) << i;
  }
}

TEST(Mapper, LeavingKeyframesAreDescribedForLoopClosureWhenAsked) {
  SyntheticWindow w(40);
  const Config config = mapperConfig();
  Mapper mapper(mapperSettings(config, false), w.camera(), w.pool());
  const PixelSelector::CornerLimits limits{150, 9.f};
  mapper.setDescribeLeavingKeyframes(true, limits);
  // The loop corners each keyframe gets are those a detector of their own finds in its image.
  PixelSelector reference(SyntheticWindow::kW, SyntheticWindow::kH, config.points);
  std::vector<Corner> expected;
  KeyframeInsertion init;
  ASSERT_TRUE(mapper.initialize(w.initialization(2), frameInfo(w, 0, w.T_c_w(0)), w.pyramid(0),
                                frameInfo(w, 2, w.T_c_w(2)), w.pyramid(2), &init));
  int described = 0;
  for (int i = 4; i < w.frames(); i += 3) {
    const KeyframeInsertion ins = mapper.addKeyframe(w.pyramid(i), frameInfo(w, i, w.T_c_w(i)));
    for (const MarginalizedKeyframe& kf : ins.map.left) {
      ++described;
      EXPECT_EQ(kf.image.width(), SyntheticWindow::kW);
      // The image it is described by is its level-0 intensity (taken from the compacted pyramid).
      const std::unique_ptr<ImagePyramid> own = w.pyramid(static_cast<int>(kf.frame_index));
      for (int y = 0; y < SyntheticWindow::kH; y += 7)
        for (int x = 0; x < SyntheticWindow::kW; x += 5)
          ASSERT_EQ(kf.image(x, y), own->gradients(0)(x, y).intensity) << "keyframe " << kf.id;
      EXPECT_EQ(kf.corner_idepth.size(), kf.corners.size());
      reference.detectCorners(*w.pyramid(static_cast<int>(kf.frame_index)), limits.max_corners,
                              limits.min_score, expected);
      ASSERT_GE(expected.size(), 10u) << "keyframe " << kf.id;
      // Every loop corner is there, or an odometry corner within 4 px of it.
      for (const Corner& g : expected) {
        bool found = false;
        for (const Eigen::Vector2f& c : kf.corners)
          found = found || (c - Eigen::Vector2f(g.u, g.v)).squaredNorm() < 16.f;
        EXPECT_TRUE(found) << "keyframe " << kf.id << ": loop corner " << g.u << " " << g.v;
      }
      EXPECT_GE(kf.corners.size(), expected.size());
    }
  }
  EXPECT_GT(described, 0);
}

TEST(Mapper, ResetHandsBackTheWindowPosesAndEmptiesIt) {
  SyntheticWindow w(8);
  Mapper mapper(mapperSettings(mapperConfig(), false), w.camera(), w.pool());
  KeyframeInsertion init;
  ASSERT_TRUE(mapper.initialize(w.initialization(2), frameInfo(w, 0, w.T_c_w(0)), w.pyramid(0),
                                frameInfo(w, 2, w.T_c_w(2)), w.pyramid(2), &init));
  mapper.addKeyframe(w.pyramid(4), frameInfo(w, 4, w.T_c_w(4)));
  const std::vector<KeyframeRecord> before = mapper.windowPoses();
  ASSERT_EQ(before.size(), 3u);
  const MapUpdate u = mapper.reset();
  EXPECT_FALSE(mapper.initialized());
  ASSERT_EQ(u.keyframes.size(), before.size());
  for (std::size_t k = 0; k < before.size(); ++k) {
    EXPECT_EQ(u.keyframes[k].id, before[k].id);
    EXPECT_TRUE(u.keyframes[k].T_w_c.matrix().isApprox(before[k].T_w_c.matrix()));
  }
  EXPECT_TRUE(mapper.reset().keyframes.empty());
}

TEST(Mapper, AnInitialisationWithTooFewPointsIsRefusedAndLeavesNoWindow) {
  SyntheticWindow w(4);
  Mapper mapper(mapperSettings(mapperConfig(), false), w.camera(), w.pool());
  InitializationResult r = w.initialization(2);
  r.points.resize(20);
  KeyframeInsertion ins;
  EXPECT_FALSE(mapper.initialize(r, frameInfo(w, 0, w.T_c_w(0)), w.pyramid(0),
                                 frameInfo(w, 2, w.T_c_w(2)), w.pyramid(2), &ins));
  EXPECT_FALSE(mapper.initialized());
  // The refused reference keyframe's pose still reaches the map (its id was used).
  EXPECT_EQ(ins.map.keyframes.size(), 1u);
}

}  // namespace
}  // namespace ldsm
