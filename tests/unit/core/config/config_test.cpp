#include <gtest/gtest.h>

#include <fstream>

#include "ldsm/config.h"
#include "ldsm/drivers/config_yaml.h"
#include "ldsm/error.h"
#include "test_paths.h"

namespace ldsm {
namespace {

std::string errorOf(const std::string& yaml) {
  try {
    drivers::parseConfigYaml(yaml, "cfg.yaml");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(Config, DefaultsAreValid) {
  EXPECT_TRUE(configProblems(Config{}).empty());
  EXPECT_NO_THROW(validateConfig(Config{}));
}

TEST(Config, RangeViolationNamesKeyAndRange) {
  Config c;
  c.points.points_per_keyframe = 5;
  c.points.corner_fraction = 1.5;
  const auto problems = configProblems(c);
  ASSERT_EQ(problems.size(), 2u);
  EXPECT_NE(problems[0].find("points.points_per_keyframe"), std::string::npos);
  EXPECT_NE(problems[0].find("[100, 20000]"), std::string::npos);
  EXPECT_NE(problems[1].find("points.corner_fraction"), std::string::npos);
  EXPECT_THROW(validateConfig(c), ConfigError);
}

TEST(Config, NanIsRejected) {
  Config c;
  c.tracking.huber_threshold = std::numeric_limits<double>::quiet_NaN();
  ASSERT_EQ(configProblems(c).size(), 1u);
  EXPECT_NE(configProblems(c)[0].find("tracking.huber_threshold"), std::string::npos);
}

TEST(Config, CrossFieldWindowBounds) {
  Config c;
  c.window.min_keyframes = 9;
  c.window.max_keyframes = 7;
  const auto problems = configProblems(c);
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_NE(problems[0].find("window.min_keyframes"), std::string::npos);
}

TEST(Config, FrameHistoryIsBoundedLiveAndWholeOfflineUnlessSet) {
  Config c;
  EXPECT_EQ(c.system.frameHistory(), 0);  // offline: every frame (loop corrections reach them)
  c.system.live = true;
  EXPECT_EQ(c.system.frameHistory(), SystemConfig::kLiveFrameHistory);  // hours on a robot
  c.system.frame_history = 0;
  EXPECT_EQ(c.system.frameHistory(), 0);
  c.system.frame_history = 300;
  c.system.live = false;
  EXPECT_EQ(c.system.frameHistory(), 300);
  c.system.frame_history = -2;
  const auto problems = configProblems(c);
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_NE(problems[0].find("system.frame_history"), std::string::npos) << problems[0];
}

TEST(ConfigYaml, DefaultsRoundTrip) {
  const std::string yaml = drivers::configToYaml(Config{});
  EXPECT_NE(yaml.find("points_per_keyframe: 2000"), std::string::npos);
  EXPECT_NE(yaml.find("[100, 20000]"), std::string::npos);
  const Config back = drivers::parseConfigYaml(yaml, "defaults.yaml");
  EXPECT_EQ(back.points.points_per_keyframe, 2000);
  EXPECT_DOUBLE_EQ(back.points.corner_fraction, Config{}.points.corner_fraction);
  EXPECT_DOUBLE_EQ(back.photometric.affine_prior_weight_unknown,
                   Config{}.photometric.affine_prior_weight_unknown);
}

TEST(ConfigYaml, ModifiedRoundTripKeepsEveryValue) {
  Config c;
  c.system.deterministic = true;
  c.points.points_per_keyframe = 1234;
  c.tracking.huber_threshold = 3.25;
  c.window.min_keyframes = 4;
  const Config back = drivers::parseConfigYaml(drivers::configToYaml(c), "m.yaml");
  EXPECT_TRUE(back.system.deterministic);
  EXPECT_EQ(back.points.points_per_keyframe, 1234);
  EXPECT_DOUBLE_EQ(back.tracking.huber_threshold, 3.25);
  EXPECT_EQ(back.window.min_keyframes, 4);
}

TEST(ConfigYaml, PartialFileKeepsDefaults) {
  const Config c = drivers::parseConfigYaml("points:\n  points_per_keyframe: 800\n", "p.yaml");
  EXPECT_EQ(c.points.points_per_keyframe, 800);
  EXPECT_EQ(c.window.max_keyframes, 7);
  EXPECT_EQ(drivers::parseConfigYaml("", "empty.yaml").points.points_per_keyframe, 2000);
}

TEST(ConfigYaml, ErrorsNameFileLineKeyAndRange) {
  std::string e = errorOf("points:\n  points_per_keyframe: 50\n");
  EXPECT_NE(e.find("cfg.yaml:2"), std::string::npos) << e;
  EXPECT_NE(e.find("points.points_per_keyframe"), std::string::npos) << e;
  EXPECT_NE(e.find("[100, 20000]"), std::string::npos) << e;

  e = errorOf("points:\n  points_per_keyframe: lots\n");
  EXPECT_NE(e.find("must be an integer"), std::string::npos) << e;

  e = errorOf("points:\n  corner_fraction: .nan\n");
  EXPECT_NE(e.find("points.corner_fraction"), std::string::npos) << e;

  e = errorOf("system:\n  deterministic: maybe\n");
  EXPECT_NE(e.find("true or false"), std::string::npos) << e;

  e = errorOf("points:\n  pionts_per_keyframe: 10\n");
  EXPECT_NE(e.find("unknown key 'points.pionts_per_keyframe'"), std::string::npos) << e;

  e = errorOf("trackign:\n  pyramid_levels: 3\n");
  EXPECT_NE(e.find("unknown key 'trackign'"), std::string::npos) << e;

  e = errorOf("points: 3\n");
  EXPECT_NE(e.find("must be a map"), std::string::npos) << e;

  e = errorOf("points: [1, 2\n");
  EXPECT_NE(e.find("not valid YAML"), std::string::npos) << e;

  // Found by fuzzing (tests/fuzz/corpus/config_yaml/crash-*): a key that is a list or a map threw
  // yaml-cpp's own exception out of the parser.
  e = errorOf("loop:\n  ? [a, b]\n  : 1\n");
  EXPECT_NE(e.find("cfg.yaml:2: a key in 'loop' is a list or a map"), std::string::npos) << e;
  e = errorOf("? {x: 1}\n: 2\n");
  EXPECT_NE(e.find("a key at the top level is a list or a map"), std::string::npos) << e;

  e = errorOf("window:\n  min_keyframes: 9\n  max_keyframes: 8\n");
  EXPECT_NE(e.find("must not exceed"), std::string::npos) << e;
  e = errorOf("loop:\n  min_matches: 12\n  min_pnp_inliers: 15\n");
  EXPECT_NE(e.find("loop.min_pnp_inliers (15) must not exceed loop.min_matches (12)"),
            std::string::npos)
      << e;
  e = errorOf("loop:\n  min_pnp_inliers: 3\n");
  EXPECT_NE(e.find("'loop.min_pnp_inliers' = 3 is outside the allowed range [10, 1000]"),
            std::string::npos)
      << e;
}

TEST(ConfigYaml, MissingFile) {
  try {
    drivers::loadConfigYaml("/nonexistent/ldsm.yaml");
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/ldsm.yaml"), std::string::npos);
  }
}

TEST(ConfigCli, PrintDefaultsAndCheck) {
  const std::string dir = test::scratchDir("config_cli");
  std::string out;
  ASSERT_EQ(test::runCommand(
                std::string(LDSM_EXE) + " config --print-defaults --out " + dir + "/d.yaml", &out),
            0)
      << out;
  ASSERT_EQ(test::runCommand(std::string(LDSM_EXE) + " config --check " + dir + "/d.yaml", &out), 0)
      << out;
  std::ofstream(dir + "/bad.yaml") << "tracking:\n  pyramid_levels: 12\n";
  EXPECT_EQ(test::runCommand(std::string(LDSM_EXE) + " config --check " + dir + "/bad.yaml", &out),
            1);
  EXPECT_NE(out.find("tracking.pyramid_levels"), std::string::npos) << out;
  EXPECT_NE(out.find("[1, 8]"), std::string::npos) << out;
}

}  // namespace
}  // namespace ldsm
