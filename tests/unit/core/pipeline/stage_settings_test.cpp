// The one mapping from the configuration tree to the stages' settings (pipeline/stage_settings.h).
#include "pipeline/stage_settings.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "ldsm/error.h"

namespace ldsm {
namespace {

TEST(StageSettings, CoarseTrackerFollowsTheConfiguration) {
  Config config;
  config.tracking.huber_threshold = 5.0;
  config.tracking.max_iterations_per_level = 4;
  config.photometric.affine_prior_weight_known = 123.0;
  config.photometric.affine_prior_weight_unknown = 0.5;
  const CoarseTrackerSettings known = coarseTrackerSettings(config, true);
  EXPECT_FLOAT_EQ(known.huber_threshold, 5.f);
  EXPECT_EQ(known.max_iterations[0], 4);
  EXPECT_EQ(known.max_iterations[1], 8);
  EXPECT_EQ(known.max_iterations[4], 20);
  EXPECT_DOUBLE_EQ(known.affine_prior_weight_a, 123.0);
  EXPECT_DOUBLE_EQ(coarseTrackerSettings(config, false).affine_prior_weight_b, 0.5);
}

TEST(StageSettings, InitializerFollowsTheConfiguration) {
  Config c;
  c.initializer.min_parallax_px = 9.0;
  c.initializer.min_rotation_free_parallax_px = 2.5;
  c.initializer.confirm_frames = 3;
  c.initializer.point_density = 1.5;
  c.points.points_per_keyframe = 1234;
  c.tracking.huber_threshold = 7.0;
  const CoarseInitializerSettings s = coarseInitializerSettings(c, 4, false);
  EXPECT_EQ(s.max_levels, 4);
  EXPECT_FLOAT_EQ(s.min_parallax_flow, 9.f);
  EXPECT_FLOAT_EQ(s.min_rotation_free_parallax, 2.5f);
  EXPECT_EQ(s.confirm_frames, 3);
  EXPECT_FLOAT_EQ(s.selector_density, 1.5f);
  EXPECT_EQ(s.selection.points_per_keyframe, 1234);
  EXPECT_FLOAT_EQ(s.huber_threshold, 7.f);
  EXPECT_NO_THROW(s.validate());
  EXPECT_GT(coarseInitializerSettings(c, 4, true).affine_prior_weight_a,
            1e3f * s.affine_prior_weight_a);

  c.initializer.min_rotation_free_parallax_px = 12.0;  // more than min_parallax_px
  const std::vector<std::string> problems = configProblems(c);
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_NE(problems[0].find("initializer.min_rotation_free_parallax_px"), std::string::npos);
  EXPECT_THROW(coarseInitializerSettings(c, 4, false).validate(), ConfigError);
}

TEST(StageSettings, MapperAndMappingStageFollowTheConfiguration) {
  Config config;
  config.window.outlier_threshold = 10.0;
  config.tracking.huber_threshold = 6.0;
  config.photometric.affine_prior_weight_unknown = 0.25;
  config.reuse.reactivated_pose_weight = 3.0;
  config.system.mapping_queue = 7;
  config.loop.corners_per_keyframe = 123;
  const MappingStageSettings s = mappingStageSettings(config, false);
  EXPECT_FLOAT_EQ(s.mapper.optimizer.residual.outlier_energy, 10.f * 10.f * kPatternSize);
  EXPECT_FLOAT_EQ(s.mapper.optimizer.residual.huber_threshold, 6.f);
  EXPECT_DOUBLE_EQ(s.mapper.optimizer.affine_prior_a, 0.25);
  EXPECT_DOUBLE_EQ(s.mapper.optimizer.reactivated_weight, 3.0);
  EXPECT_FLOAT_EQ(s.mapper.trace_outlier_threshold, 10.f);
  EXPECT_EQ(s.queue_capacity, 7);
  EXPECT_EQ(s.loop_corners, 123);
  EXPECT_FLOAT_EQ(s.tracker.huber_threshold, 6.f);
}

TEST(StageSettings, StructDefaultsAgreeWithTheConfigurationDefaults) {
  // A stage built from its settings' defaults behaves as one built from the default Config.
  const MappingStageSettings defaults;
  const MappingStageSettings configured = mappingStageSettings(Config{}, false);
  EXPECT_EQ(defaults.queue_capacity, configured.queue_capacity);
  EXPECT_EQ(defaults.loop_corners, configured.loop_corners);
  EXPECT_FLOAT_EQ(defaults.loop_corner_min_score, configured.loop_corner_min_score);
}

}  // namespace
}  // namespace ldsm

namespace ldsm {
namespace {

TEST(StageSettings, ParallelThreadsAreOneWhenDeterministicAndTheCoresOtherwise) {
  Config config;
  config.system.deterministic = true;
  EXPECT_EQ(parallelThreads(config), 1);
  EXPECT_EQ(trackingStageSettings(config, 5, false).parallel_threads, 1);
  config.system.deterministic = false;
  const int automatic = parallelThreads(config);
  EXPECT_GE(automatic, 1);
  EXPECT_LE(automatic, SystemConfig::kMaxAutomaticParallelThreads);
  config.system.parallel_threads = 3;  // given: also in deterministic mode (results equal)
  config.system.deterministic = true;
  EXPECT_EQ(parallelThreads(config), 3);
  EXPECT_EQ(trackingStageSettings(config, 5, false).parallel_threads, 3);
  config.system.parallel_threads = 65;
  const auto problems = configProblems(config);
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_NE(problems[0].find("system.parallel_threads"), std::string::npos) << problems[0];
}

}  // namespace
}  // namespace ldsm
