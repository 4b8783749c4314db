// `ldsm info` on fixtures: the report of a good dataset (exit 0) and clear errors with a non-zero
// exit code on bad input. Needs the `ldsm` target built.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>

#include "dataset_fixtures.h"

namespace ldsm::test {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

#ifdef LDSM_EXE
/// Runs `ldsm <args>`, returning the exit code; skips the test when the tool is not built.
int runLdsm(const std::string& args, std::string* output) {
  return runCommand(std::string("'") + LDSM_EXE + "' " + args, output);
}
#define REQUIRE_LDSM_EXE() \
  if (!std::filesystem::exists(LDSM_EXE)) GTEST_SKIP() << "build target ldsm first"
#else
int runLdsm(const std::string&, std::string*) {
  return -1;
}
#define REQUIRE_LDSM_EXE() GTEST_SKIP() << "the ldsm tool is not part of this build"
#endif

std::string quoted(const std::string& s) {
  return "'" + s + "'";
}

TEST(LdsmInfo, ReportsAGoodTumMonoDataset) {
  REQUIRE_LDSM_EXE();
  const std::string dir = testDir();
  writeTumMonoFixture(dir, 5, false);
  std::string out;
  ASSERT_EQ(runLdsm("info --dataset " + quoted(dir), &out), 0) << out;
  EXPECT_THAT(out, HasSubstr("layout:       tum-mono\n"));
  EXPECT_THAT(out, HasSubstr("frames:       5\n"));
  EXPECT_THAT(out, HasSubstr("resolution:   24 x 16\n"));
  EXPECT_THAT(out, HasSubstr("0.000000 .. 0.200000 s (duration 0.200 s, mean 20.000 fps)"));
  EXPECT_THAT(out, HasSubstr("exposure:     known for 5 of 5 frames, 10.000 .. 14.000 ms"));
  EXPECT_THAT(out, HasSubstr(dir + "/camera.txt (dso-camera)\n              input: Pinhole"));
  EXPECT_THAT(out, HasSubstr(dir + "/pcalib.txt (response)"));
  EXPECT_THAT(out, HasSubstr(dir + "/vignette.png (vignette)"));
  EXPECT_THAT(out, HasSubstr(dir + "/groundtruth.txt (tum, 5 poses"));

  ASSERT_EQ(runLdsm("info --verify --format tum-mono --dataset " + quoted(dir), &out), 0) << out;
  EXPECT_THAT(out, HasSubstr("verified:     all 5 frames decode at 24 x 16"));
}

TEST(LdsmInfo, ReportsKittiPosesWithoutTumGroundTruth) {
  REQUIRE_LDSM_EXE();
  const std::string dir = testDir();
  writeKittiFixture(dir, 3);
  std::string out;
  ASSERT_EQ(runLdsm("info --dataset " + quoted(dir), &out), 0) << out;
  EXPECT_THAT(out, HasSubstr("layout:       kitti\n"));
  EXPECT_THAT(out, HasSubstr("calib.txt (kitti-calib)"));
  EXPECT_THAT(out, HasSubstr("poses/04.txt (kitti, 3 poses, 0.000000 .. 0.200000 s)"));
}

TEST(LdsmInfo, ParsesTheEurocSensorYaml) {
  REQUIRE_LDSM_EXE();
  const std::string dir = testDir();
  writeEurocFixture(dir, 2);
  std::string out;
  ASSERT_EQ(runLdsm("info --dataset " + quoted(dir), &out), 0) << out;
  EXPECT_THAT(out, HasSubstr("layout:       euroc\n"));
  EXPECT_THAT(out, HasSubstr("sensor.yaml (camera-yaml)"));
  EXPECT_THAT(out, HasSubstr("fy=21"));
  EXPECT_THAT(out, HasSubstr("ground truth: none\n"));
}

TEST(LdsmInfo, BrokenCalibrationIsReportedAndFails) {
  REQUIRE_LDSM_EXE();
  const std::string dir = testDir();
  writeTumMonoFixture(dir, 2, false);
  writeText(dir + "/camera.txt", "Pinhole 20 20 12\n24 16\nnone\n24 16\n");
  std::string out;
  EXPECT_NE(runLdsm("info --dataset " + quoted(dir), &out), 0);
  EXPECT_THAT(out, HasSubstr("layout:       tum-mono\n"));
  EXPECT_THAT(out, HasSubstr("error: " + dir + "/camera.txt:1"));
}

TEST(LdsmInfo, MissingDatasetFailsWithMessage) {
  REQUIRE_LDSM_EXE();
  const std::string missing = testDir() + "/missing";
  std::string out;
  EXPECT_NE(runLdsm("info --dataset " + quoted(missing), &out), 0);
  EXPECT_THAT(out, HasSubstr("ldsm: error: " + missing + ": no such file or directory"));
}

TEST(LdsmInfo, MalformedTimesFailsNamingTheLine) {
  REQUIRE_LDSM_EXE();
  const std::string dir = testDir();
  writeTumMonoFixture(dir, 3, false);
  writeText(dir + "/times.txt", "00000 0.0\n00001 zero\n00002 0.2\n");
  std::string out;
  EXPECT_NE(runLdsm("info --dataset " + quoted(dir), &out), 0);
  EXPECT_THAT(out, HasSubstr("ldsm: error: " + dir + "/times.txt:2: "));
}

TEST(LdsmInfo, VerifyFindsAnUnreadableImage) {
  REQUIRE_LDSM_EXE();
  const std::string dir = testDir();
  writeTumMonoFixture(dir, 3, false);
  writeText(dir + "/images/00001.png", "garbage");
  std::string out;
  ASSERT_EQ(runLdsm("info --dataset " + quoted(dir), &out), 0) << out;  // describe is cheap
  EXPECT_NE(runLdsm("info --verify --dataset " + quoted(dir), &out), 0);
  EXPECT_THAT(out, HasSubstr(dir + "/images/00001.png: cannot decode"));
}

TEST(LdsmInfo, BrokenGroundTruthIsReportedAndFails) {
  REQUIRE_LDSM_EXE();
  const std::string dir = testDir();
  writeTumMonoFixture(dir, 3, false);
  writeText(dir + "/groundtruth.txt", "0.0 1 2 3\n");
  std::string out;
  EXPECT_NE(runLdsm("info --dataset " + quoted(dir), &out), 0);
  EXPECT_THAT(out, HasSubstr("frames:       3\n"));
  EXPECT_THAT(out, HasSubstr("error: " + dir + "/groundtruth.txt:1"));
}

TEST(LdsmInfo, UnknownFormatNameIsRejected) {
  REQUIRE_LDSM_EXE();
  const std::string dir = testDir();
  writeTumMonoFixture(dir, 2, false);
  std::string out;
  EXPECT_NE(runLdsm("info --format tum_mono --dataset " + quoted(dir), &out), 0);
  EXPECT_THAT(out, HasSubstr("tum_mono"));
  EXPECT_THAT(out, Not(HasSubstr("layout:")));
}

}  // namespace
}  // namespace ldsm::test
