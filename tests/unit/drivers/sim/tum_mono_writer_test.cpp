// writeTumMonoSequence round trip through the dataset and calibration readers, and the `ldsm sim`
// command line.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "ldsm/calib/dso_camera_file.h"
#include "ldsm/calib/photometric_files.h"
#include "ldsm/drivers/dataset_description.h"
#include "ldsm/drivers/dataset_source.h"
#include "ldsm/drivers/sim/tum_mono_writer.h"
#include "ldsm/drivers/trajectory_io.h"
#include "ldsm/error.h"
#include "sim_test_support.h"

namespace ldsm::drivers::sim {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  const fs::path p = fs::path(LDSM_TEST_TMP) / "sim" / name;
  fs::remove_all(p);
  fs::create_directories(p.parent_path());
  return p;
}

SimOptions smallOptions(std::int64_t frames) {
  SimOptions o;
  o.width = 96;
  o.height = 72;
  o.frames = frames;
  o.exposure_changes = true;
  return o;
}

TEST(TumMonoWriter, RoundTripThroughTheReaders) {
  const fs::path dir = scratch("roundtrip");
  SimSource src(test::sharedScene("short"), smallOptions(8));
  TumMonoWriteOptions w;
  w.focal_error = 0.03;
  int calls = 0;
  const TumMonoWriteSummary s =
      writeTumMonoSequence(src, dir.string(), w, [&](std::int64_t done, std::int64_t total) {
        EXPECT_EQ(done, ++calls);
        EXPECT_EQ(total, 8);
      });
  EXPECT_EQ(calls, 8);
  EXPECT_EQ(s.frames, 8);
  EXPECT_NEAR(s.path_length_m, pathLength(src.groundTruth()), 1e-12);
  EXPECT_GT(s.path_length_m, 0.0);
  for (const char* f : {"times.txt", "camera.txt", "pcalib.txt", "vignette.png", "groundtruth.txt"})
    EXPECT_TRUE(fs::is_regular_file(dir / f)) << f;

  // The dataset reader sees a TUM-Mono sequence with everything beside it.
  const DatasetDescription d = describeDataset(dir.string());
  EXPECT_EQ(d.format, DatasetFormat::TumMono);
  ASSERT_EQ(d.frame_count, 8);
  EXPECT_EQ(d.width, 96);
  EXPECT_EQ(d.height, 72);
  EXPECT_FALSE(d.groundtruth_file.empty());
  EXPECT_FALSE(d.photometric_response_file.empty());
  EXPECT_FALSE(d.vignette_file.empty());
  for (int i = 0; i < 8; ++i) {
    EXPECT_DOUBLE_EQ(d.timestamps[i], src.groundTruth()[i].timestamp);
    EXPECT_NEAR(d.exposures_ms[i], src.exposureMs(i), 1e-12);
  }

  // Images decode losslessly to the rendered frames.
  auto reader = openDataset(d);
  Frame read, rendered;
  for (int i = 0; i < 8; ++i) {
    ASSERT_TRUE(reader->next(read));
    src.renderFrame(i, rendered);
    EXPECT_EQ(test::fnv1a(read.image), test::fnv1a(rendered.image)) << "frame " << i;
  }
  EXPECT_FALSE(reader->next(read));
  const cv::Mat png = cv::imread((dir / "images" / "00000.png").string(), cv::IMREAD_UNCHANGED);
  EXPECT_EQ(png.cols, 96);
  EXPECT_EQ(png.rows, 72);
  EXPECT_EQ(png.type(), CV_8UC1);

  // Calibration files: the focal length carries the requested error, the rest is exact.
  const GeometricCalibration g = calib::readDsoCameraFile((dir / "camera.txt").string());
  EXPECT_NEAR(g.input.fx, 1.03 * src.intrinsics().fx, 1e-9);
  EXPECT_NEAR(g.input.fy, 1.03 * src.intrinsics().fy, 1e-9);
  EXPECT_EQ(g.input.cx, src.intrinsics().cx);
  EXPECT_EQ(g.output.mode, OutputMode::None);
  const auto inv = calib::readInverseResponse((dir / "pcalib.txt").string());
  for (int v = 0; v < 256; ++v) EXPECT_EQ(inv[v], src.photometricCalibration().inverse_response[v]);
  const ImageF V = calib::readVignette((dir / "vignette.png").string());
  ASSERT_EQ(V.width(), 96);
  for (int y = 0; y < 72; y += 7)
    for (int x = 0; x < 96; x += 7)
      EXPECT_NEAR(V(x, y), src.photometricCalibration().vignette(x, y), 1e-4);

  // Ground truth reads back pose for pose.
  const Trajectory gt = readTrajectory((dir / "groundtruth.txt").string());
  ASSERT_EQ(gt.size(), 8u);
  for (int i = 0; i < 8; ++i) {
    EXPECT_DOUBLE_EQ(gt[i].timestamp, src.groundTruth()[i].timestamp);
    EXPECT_LT((gt[i].pose.translation - src.groundTruth()[i].pose.translation).norm(), 1e-12);
    EXPECT_LT(test::rotationAngle(gt[i].pose, src.groundTruth()[i].pose), 1e-9);
  }

  // times.txt has one line per frame.
  std::ifstream times(dir / "times.txt");
  int lines = 0;
  for (std::string line; std::getline(times, line);) lines += !line.empty();
  EXPECT_EQ(lines, 8);

  // A shorter run into the same folder leaves no stale frames behind.
  SimSource shorter(test::sharedScene("short"), smallOptions(3));
  std::int64_t last = 0;
  writeTumMonoSequence(shorter, dir.string(),
                       [&](std::int64_t done, std::int64_t) { last = done; });
  EXPECT_EQ(last, 3);
  EXPECT_EQ(describeDataset(dir.string()).frame_count, 3);
  EXPECT_FALSE(fs::exists(dir / "images" / "00005.png"));
}

TEST(TumMonoWriter, RejectsBadFocalErrorAndUnwritableFolders) {
  SimSource src(test::sharedScene("short"), smallOptions(2));
  TumMonoWriteOptions w;
  w.focal_error = 0.7;
  EXPECT_THROW(writeTumMonoSequence(src, scratch("bad_focal").string(), w), ConfigError);
  const fs::path file = scratch("a_file");
  std::ofstream(file.string()) << "x";
  try {
    writeTumMonoSequence(src, (file / "out").string());
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("a_file"), std::string::npos) << e.what();
  }
}

#ifdef LDSM_EXE
int run(const std::string& args, std::string* output = nullptr) {
  const fs::path log = scratch("cli.log");
  const std::string cmd =
      std::string("\"") + LDSM_EXE + "\" " + args + " > \"" + log.string() + "\" 2>&1";
  const int status = std::system(cmd.c_str());
  if (output != nullptr) {
    output->clear();
    std::ifstream in(log);
    for (std::string line; std::getline(in, line);) *output += line + "\n";
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(SimCommand, RendersAFolderAndReportsErrors) {
  if (!fs::exists(LDSM_EXE)) GTEST_SKIP() << "build the ldsm target first: " << LDSM_EXE;
  const fs::path dir = scratch("cli_out");
  std::string out;
  ASSERT_EQ(
      run("sim --scene short --frames 4 --width 64 --height 48 --noise 0.5 --exposure-changes "
          "--response scurve --vignette 0.2 --focal-error 0.01 --seed 3 --out \"" +
              dir.string() + "\"",
          &out),
      0)
      << out;
  EXPECT_NE(out.find("path length"), std::string::npos) << out;
  EXPECT_NE(out.find("frames:       4"), std::string::npos) << out;
  EXPECT_EQ(describeDataset(dir.string()).frame_count, 4);
  EXPECT_EQ(run("sim --list", &out), 0);
  EXPECT_NE(out.find("loop"), std::string::npos) << out;
  EXPECT_EQ(run("sim --scene nowhere --out \"" + dir.string() + "\"", &out), 1);
  EXPECT_NE(out.find("valid scenes"), std::string::npos) << out;
  EXPECT_EQ(run("sim --scene short --width 4 --out \"" + dir.string() + "\"", &out), 1);
  EXPECT_NE(out.find("width"), std::string::npos) << out;
  EXPECT_NE(run("sim --scene short --response wobbly --out \"" + dir.string() + "\"", &out), 0);
}
#endif

}  // namespace
}  // namespace ldsm::drivers::sim
