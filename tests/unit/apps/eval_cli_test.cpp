// Runs the `ldsm eval` tool (LDSM_EXE) on files written here.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "ldsm/drivers/trajectory_io.h"
#include "synthetic_trajectory.h"

namespace ldsm::eval {
namespace {

struct RunResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr
};

RunResult runLdsm(const std::string& args) {
  RunResult r;
  const std::string cmd = std::string("\"") + LDSM_EXE + "\" " + args + " 2>&1";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (pipe == nullptr) return r;
  std::array<char, 4096> buf;
  std::size_t n = 0;
  while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) r.output.append(buf.data(), n);
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

class EvalCli : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(std::filesystem::exists(LDSM_EXE)) << "build the `ldsm` target first";
    dir_ = testing::scratchDir("cli");
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string dir_;
};

TEST_F(EvalCli, SummaryJsonAndPlots) {
  const Trajectory gt = testing::curvedTrajectory(300);
  Trajectory est =
      testing::transformed(gt, testing::makeSim3(0.5, {0, 1, 0}, {1, 2, 3}, 0.5).inverse());
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.002);
  for (auto& sp : est) sp.pose.translation += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
  drivers::writeTumTrajectory(dir_ + "/gt.txt", gt);
  drivers::writeKittiPoses(dir_ + "/est_kitti.txt", est);
  {
    std::ofstream times(dir_ + "/times.txt");
    times.precision(17);
    for (const auto& sp : est) times << sp.timestamp << "\n";
  }

  const std::string common = "eval --gt " + dir_ + "/gt.txt --est " + dir_ +
                             "/est_kitti.txt --est-times " + dir_ + "/times.txt";
  const RunResult png = runLdsm(common + " --json " + dir_ + "/r.json --plot " + dir_ + "/p.png");
  ASSERT_EQ(png.exit_code, 0) << png.output;
  EXPECT_EQ(png.output.rfind("ATE rmse ", 0), 0u) << png.output;
  EXPECT_NE(png.output.find("over 300 poses"), std::string::npos) << png.output;
  EXPECT_NE(png.output.find("RPE "), std::string::npos) << png.output;
  EXPECT_NE(png.output.find("e_align "), std::string::npos) << png.output;
  double rmse = -1.0;
  ASSERT_EQ(std::sscanf(png.output.c_str(), "ATE rmse %lf", &rmse), 1);
  // 2 mm of noise on an estimate at twice the scale: 1 mm per axis after alignment.
  EXPECT_NEAR(rmse, 0.001 * std::sqrt(3.0), 0.0003);

  const std::string json = slurp(dir_ + "/r.json");
  for (const char* key : {"\"ate\"", "\"rmse\"", "\"matched\": 300", "\"sim3_scale\"", "\"rpe\"",
                          "\"translation_percent\"", "\"loop_drift\"", "\"e_align\"", "\"e_s\"",
                          "\"format\": \"kitti\""}) {
    EXPECT_NE(json.find(key), std::string::npos) << key << " missing in\n" << json;
  }
  const std::string png_data = slurp(dir_ + "/p.png");
  ASSERT_GT(png_data.size(), 1000u);
  EXPECT_EQ(png_data.substr(1, 3), "PNG");

  const RunResult svg = runLdsm(common + " --align se3 --plot " + dir_ + "/p.svg");
  ASSERT_EQ(svg.exit_code, 0) << svg.output;
  const std::string svg_data = slurp(dir_ + "/p.svg");
  EXPECT_EQ(svg_data.rfind("<?xml", 0), 0u);
  EXPECT_NE(svg_data.find("<polyline"), std::string::npos);
  EXPECT_NE(svg_data.find("ground truth"), std::string::npos);
  EXPECT_NE(svg_data.find("</svg>"), std::string::npos);
}

TEST_F(EvalCli, BadInputFails) {
  drivers::writeTumTrajectory(dir_ + "/gt.txt", testing::curvedTrajectory(50));
  {
    std::ofstream bad(dir_ + "/bad.txt");
    bad << "0 1 2 3 0 0 0 1\n0.1 1 2 x 0 0 0 1\n";
  }
  const RunResult r = runLdsm("eval --gt " + dir_ + "/gt.txt --est " + dir_ + "/bad.txt");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find(dir_ + "/bad.txt:2:"), std::string::npos) << r.output;

  const RunResult missing = runLdsm("eval --gt " + dir_ + "/gt.txt --est " + dir_ + "/none.txt");
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_NE(missing.output.find("none.txt"), std::string::npos) << missing.output;

  const RunResult plot =
      runLdsm("eval --gt " + dir_ + "/gt.txt --est " + dir_ + "/gt.txt --plot " + dir_ + "/p.jpg");
  EXPECT_NE(plot.exit_code, 0);
  EXPECT_NE(plot.output.find(".png or .svg"), std::string::npos) << plot.output;

  const RunResult format =
      runLdsm("eval --gt " + dir_ + "/gt.txt --est " + dir_ + "/gt.txt --est-format kitti");
  EXPECT_NE(format.exit_code, 0);
  EXPECT_NE(format.output.find("gt.txt:"), std::string::npos) << format.output;
}

// --align-as: the second session of a saved map is measured under the first session's alignment.
TEST_F(EvalCli, AlignAsMeasuresASecondSessionInTheFirstOnesFrame) {
  const Trajectory gt = testing::curvedTrajectory(300);
  const Alignment g = testing::makeSim3(0.5, {0, 1, 0}, {1, 2, 3}, 0.5);
  const Trajectory first = testing::transformed(gt, g.inverse());
  // The second session: the last 100 poses, 4 cm off in the map frame (2 cm in gt units).
  Trajectory second(first.begin() + 200, first.end());
  for (StampedPose& sp : second) sp.pose.translation += Eigen::Vector3d(0.04, 0.0, 0.0);
  drivers::writeTumTrajectory(dir_ + "/gt.txt", gt);
  drivers::writeTumTrajectory(dir_ + "/first.txt", first);
  drivers::writeTumTrajectory(dir_ + "/second.txt", second);

  const RunResult r = runLdsm("eval --gt " + dir_ + "/gt.txt --est " + dir_ + "/second.txt" +
                              " --align-as " + dir_ + "/first.txt --json " + dir_ + "/s.json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  double own = -1.0;
  ASSERT_EQ(std::sscanf(r.output.c_str(), "ATE rmse %lf", &own), 1) << r.output;
  EXPECT_LT(own, 1e-6);  // its own alignment hides the offset
  const std::size_t at = r.output.find("\nATE rmse ");
  ASSERT_NE(at, std::string::npos) << r.output;
  double under = -1.0, reference = -1.0;
  ASSERT_EQ(std::sscanf(r.output.c_str() + at + 1,
                        "ATE rmse %lf m over 100 poses under the alignment of the reference "
                        "(which has %lf m under its own)",
                        &under, &reference),
            2)
      << r.output;
  EXPECT_NEAR(under, 0.02, 1e-5);
  EXPECT_LT(reference, 1e-6);
  const std::string json = slurp(dir_ + "/s.json");
  for (const char* key : {"\"align_as\"", "\"reference_rmse\"", "\"reference_matched\": 300"})
    EXPECT_NE(json.find(key), std::string::npos) << key << " missing in\n" << json;

  const RunResult missing = runLdsm("eval --gt " + dir_ + "/gt.txt --est " + dir_ +
                                    "/second.txt --align-as " + dir_ + "/none.txt");
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_NE(missing.output.find("none.txt"), std::string::npos) << missing.output;

  // A KITTI reference without its timestamps cannot be matched with a timed ground truth.
  drivers::writeKittiPoses(dir_ + "/first_kitti.txt", first);
  const RunResult untimed = runLdsm("eval --gt " + dir_ + "/gt.txt --est " + dir_ +
                                    "/second.txt --align-as " + dir_ + "/first_kitti.txt");
  EXPECT_NE(untimed.exit_code, 0);
  EXPECT_NE(untimed.output.find("first_kitti.txt: KITTI poses carry no timestamps; pass "
                                "--align-as-times"),
            std::string::npos)
      << untimed.output;
}

TEST_F(EvalCli, SharedGroundTruthAgainstItself) {
  const std::string gt = std::string(LDSM_SHARED_DATA) + "/vamr_desk_loop/groundtruth.txt";
  if (!std::filesystem::exists(gt)) GTEST_SKIP() << "../shared/data absent: " << gt;
  const RunResult r = runLdsm("eval --gt " + gt + " --est " + gt + " --json " + dir_ + "/v.json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  double rmse = -1.0;
  ASSERT_EQ(std::sscanf(r.output.c_str(), "ATE rmse %lf", &rmse), 1) << r.output;
  EXPECT_LT(rmse, 1e-9);
  EXPECT_NE(r.output.find("over 736 poses"), std::string::npos) << r.output;
  EXPECT_NE(slurp(dir_ + "/v.json").find("\"e_align\""), std::string::npos);
}

}  // namespace
}  // namespace ldsm::eval
