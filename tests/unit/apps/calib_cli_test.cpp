// `ldsm calib` end to end on data rendered by `ldsm calib synth`.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "ldsm/calib/dso_camera_file.h"
#include "ldsm/calib/image_file.h"
#include "ldsm/calib/kalibr_yaml.h"
#include "ldsm/calib/photometric_files.h"
#include "test_paths.h"

namespace ldsm::calib {
namespace {

namespace fs = std::filesystem;

#ifdef LDSM_EXE
int ldsm(const std::string& args, std::string* output) {
  return test::runCommand(std::string("\"") + LDSM_EXE + "\" " + args, output);
}

std::string readText(const fs::path& p) {
  std::ifstream in(p);
  std::string text;
  for (std::string line; std::getline(in, line);) text += line + "\n";
  return text;
}

/// Decodes a PNG written by the tool and returns its size and channel count.
ImageFileInfo pngInfo(const fs::path& p) {
  ImageU8 img;
  return readImage(p.string(), img);
}

class CalibCli : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(LDSM_EXE)) GTEST_SKIP() << "build the ldsm target first: " << LDSM_EXE;
  }
};

TEST_F(CalibCli, CameraFromSynthesizedBoardViews) {
  const fs::path dir = test::scratchDir("calib_cli_camera");
  std::string out;
  ASSERT_EQ(ldsm("calib synth --kind board --views 12 --blurred 1 --duplicates 1 --width 320 "
                 "--height 240 --out \"" +
                     (dir / "data").string() + "\"",
                 &out),
            0)
      << out;
  ASSERT_EQ(ldsm("calib camera --images \"" + (dir / "data/images").string() +
                     "\" --board chessboard --cols 9 --rows 6 --square 0.03 --model radtan "
                     "--out \"" +
                     (dir / "result").string() + "\"",
                 &out),
            0)
      << out;
  EXPECT_NE(out.find("views:        12 used of 14"), std::string::npos) << out;
  EXPECT_NE(out.find("reprojection: RMS"), std::string::npos) << out;
  const auto truth = readDsoCameraFile((dir / "data/true_camera.txt").string());
  const auto got = readDsoCameraFile((dir / "result/camera.txt").string());
  EXPECT_NEAR(got.input.fx, truth.input.fx, 0.005 * truth.input.fx);
  EXPECT_NEAR(got.input.cy, truth.input.cy, 1.0);
  EXPECT_EQ(readKalibrCameraYaml((dir / "result/camchain.yaml").string()).input.fx, got.input.fx);
  const std::string report = readText(dir / "result/calibration_report.txt");
  EXPECT_NE(report.find(" blurred "), std::string::npos) << report;
  EXPECT_NE(report.find(" duplicate "), std::string::npos) << report;
  const auto plot = pngInfo(dir / "result/coverage.png");
  EXPECT_EQ(plot.channels, 3);
  EXPECT_GT(plot.width, 640);
}

TEST_F(CalibCli, ResponseThenVignetteFromSynthesizedData) {
  const fs::path dir = test::scratchDir("calib_cli_photometric");
  std::string out;
  ASSERT_EQ(ldsm("calib synth --kind sweep --width 160 --height 120 --response scurve --out \"" +
                     (dir / "sweep").string() + "\"",
                 &out),
            0)
      << out;
  ASSERT_EQ(ldsm("calib response --sweep \"" + (dir / "sweep").string() + "\" --reference \"" +
                     (dir / "sweep/true_pcalib.txt").string() + "\" --out \"" +
                     (dir / "response").string() + "\"",
                 &out),
            0)
      << out;
  EXPECT_NE(out.find("monotonic:    yes"), std::string::npos) << out;
  const auto g = readInverseResponse((dir / "response/pcalib.txt").string());
  const auto truth = readInverseResponse((dir / "sweep/true_pcalib.txt").string());
  double s = 0;
  for (std::size_t k = 0; k < 256; ++k) s += (g[k] - truth[k]) * (g[k] - truth[k]);
  EXPECT_LT(std::sqrt(s / 256), 0.015 * 255);
  EXPECT_EQ(pngInfo(dir / "response/response.png").channels, 3);

  ASSERT_EQ(ldsm("calib synth --kind flat --width 160 --height 120 --response scurve --vignette "
                 "0.5 --out \"" +
                     (dir / "flat").string() + "\"",
                 &out),
            0)
      << out;
  ASSERT_EQ(ldsm("calib vignette --images \"" + (dir / "flat").string() + "\" --pcalib \"" +
                     (dir / "response/pcalib.txt").string() + "\" --out \"" +
                     (dir / "vignette").string() + "\"",
                 &out),
            0)
      << out;
  const ImageF v = readVignette((dir / "vignette/vignette.png").string());
  const ImageF tv = readVignette((dir / "flat/true_vignette.png").string());
  ASSERT_EQ(v.width(), 160);
  double e = 0;
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 160; ++x) e += std::pow(v(x, y) - tv(x, y), 2);
  // With the recovered (not the true) response.
  EXPECT_LT(std::sqrt(e / (160 * 120)), 0.01);
  EXPECT_EQ(pngInfo(dir / "vignette/vignette_plot.png").channels, 3);
}

TEST_F(CalibCli, BadInputSaysWhatToDo) {
  const fs::path dir = test::scratchDir("calib_cli_errors");
  std::string out;
  ASSERT_EQ(ldsm("calib synth --kind flat --width 160 --height 120 --out \"" +
                     (dir / "flat").string() + "\"",
                 &out),
            0)
      << out;
  // No board in pictures of a wall.
  EXPECT_EQ(ldsm("calib camera --images \"" + (dir / "flat/images").string() +
                     "\" --cols 9 --rows 6 --square 0.03 --out \"" + (dir / "c").string() + "\"",
                 &out),
            1);
  EXPECT_NE(out.find("board was not found in any of the 8 images"), std::string::npos) << out;
  // A sweep without exposure times.
  std::ofstream(dir / "flat/times.txt")
      << "0 0.0\n1 0.1\n2 0.2\n3 0.3\n4 0.4\n5 0.5\n6 0.6\n7 0.7\n";
  EXPECT_EQ(ldsm("calib response --sweep \"" + (dir / "flat").string() + "\" --out \"" +
                     (dir / "r").string() + "\"",
                 &out),
            1);
  EXPECT_NE(out.find("times.txt: no exposure times"), std::string::npos) << out;
  // Both or neither input.
  EXPECT_EQ(ldsm("calib response --out x", &out), 1);
  EXPECT_NE(out.find("give either --sweep"), std::string::npos) << out;
  // A missing response file.
  EXPECT_EQ(ldsm("calib vignette --images \"" + (dir / "flat").string() +
                     "\" --pcalib nowhere.txt --out \"" + (dir / "v").string() + "\"",
                 &out),
            1);
  EXPECT_NE(out.find("nowhere.txt"), std::string::npos) << out;
  // Squares given as inner corners is caught by the board check only when < 3.
  EXPECT_EQ(ldsm("calib board --cols 2 --rows 5 --square 0.03 --out b.png", &out), 1);
  EXPECT_NE(out.find("--cols and --rows count the board's squares"), std::string::npos) << out;
}

TEST_F(CalibCli, WritesAPrintableBoard) {
  const fs::path dir = test::scratchDir("calib_cli_board");
  std::string out;
  ASSERT_EQ(ldsm("calib board --board charuco --cols 7 --rows 5 --square 0.04 --marker 0.03 "
                 "--dictionary DICT_4X4_50 --px-per-square 60 --out \"" +
                     (dir / "board.png").string() + "\"",
                 &out),
            0)
      << out;
  const auto info = pngInfo(dir / "board.png");
  EXPECT_EQ(info.width, 7 * 60 + 60);
  EXPECT_EQ(info.height, 5 * 60 + 60);
}
#endif

}  // namespace
}  // namespace ldsm::calib
