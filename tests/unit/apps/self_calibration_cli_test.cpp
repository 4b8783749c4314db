// `ldsm run` on a camera without a calibration (--fov) and the refined camera it writes
// (camera.txt, camchain.yaml, the history in stats.json): docs/engine.md, self-calibration.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <string>

#include "ldsm/calib/dso_camera_file.h"
#include "ldsm/calib/kalibr_yaml.h"
#include "ldsm/drivers/sim/sim_source.h"
#include "ldsm/drivers/sim/tum_mono_writer.h"
#include "test_paths.h"

namespace ldsm {
namespace {

#if defined(LDSM_EXE)

/// A 60-frame synthetic corridor at 320x240 (horizontal field of view 80 degrees) in TUM-Mono
/// layout, once with its camera.txt and once without.
class SelfCalibrationCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = test::scratchDir("self_calibration_" + std::to_string(::getpid()));
    drivers::sim::SimOptions o;
    o.width = 320;
    o.height = 240;
    o.frames = 60;
    drivers::sim::SimSource source("forward", o);
    drivers::sim::writeTumMonoSequence(source, dir_ + "/seq");
    std::filesystem::copy(dir_ + "/seq", dir_ + "/uncalibrated",
                          std::filesystem::copy_options::recursive);
    std::filesystem::remove(dir_ + "/uncalibrated/camera.txt");
  }
  static void TearDownTestSuite() { std::filesystem::remove_all(dir_); }

  static int run(const std::string& args, std::string* log) {
    return test::runCommand(std::string(LDSM_EXE) + " run " + args + " 2>&1", log);
  }
  static std::string dir_;
};

std::string SelfCalibrationCli::dir_;

TEST_F(SelfCalibrationCli, WithoutACalibrationTheErrorSaysHowToStart) {
  std::string log;
  EXPECT_NE(
      run("--deterministic --dataset " + dir_ + "/uncalibrated --out " + dir_ + "/none", &log), 0);
  EXPECT_NE(log.find("no calibration found"), std::string::npos) << log;
  EXPECT_NE(log.find("--fov DEG"), std::string::npos) << log;
}

TEST_F(SelfCalibrationCli, AFieldOfViewGuessStartsAndWritesTheRefinedCamera) {
  const std::string out = dir_ + "/fov";
  std::string log;
  ASSERT_EQ(run("--deterministic --fov 80 --dataset " + dir_ + "/uncalibrated --out " + out, &log),
            0)
      << log;
  EXPECT_NE(log.find("self-calibrating from a pinhole guess"), std::string::npos) << log;
  EXPECT_NE(log.find("finished: 60 frames"), std::string::npos) << log;
  // The camera it ended with, in both formats, readable by the loaders of --calib.
  const GeometricCalibration txt = calib::readDsoCameraFile(out + "/camera.txt");
  const GeometricCalibration yaml = calib::readKalibrCameraYaml(out + "/camchain.yaml");
  EXPECT_EQ(txt.input.width, 320);
  EXPECT_EQ(txt.input.fx, yaml.input.fx);
  // The guess is this scene's true camera (80 degrees over 320 pixels: fx 190.7): on a short
  // forward corridor the refinement has no reason to move it far.
  EXPECT_NEAR(txt.input.fx, 190.68, 0.02 * 190.68);
  EXPECT_NEAR(txt.input.cx, 159.5, 3.0);
  const std::string camera = test::readFile(out + "/camera.txt");
  EXPECT_NE(camera.find("from a pinhole guess of 80 degrees (--fov)"), std::string::npos) << camera;
  const std::string stats = test::readFile(out + "/stats.json");
  const auto history = stats.find("\"history\": [");
  ASSERT_NE(history, std::string::npos) << stats;
  EXPECT_EQ(stats.find("\"windows\": 1,", history), stats.find("\"windows\"", history)) << stats;
  // Each sample of the history has both uncertainties, the formal and the realistic.
  EXPECT_NE(stats.find("\"sigma_realistic\": [", history), std::string::npos) << stats;
  EXPECT_NE(stats.find("\"sigma_px\""), std::string::npos);
  EXPECT_NE(stats.find("\"sigma_px_realistic\""), std::string::npos);
  EXPECT_NE(stats.find("\"sigma_realistic\""), std::string::npos);
  EXPECT_NE(camera.find("1-sigma (realistic"), std::string::npos) << camera;
  // The written camera starts the next run.
  ASSERT_EQ(run("--deterministic --calib " + out + "/camera.txt --dataset " + dir_ +
                    "/uncalibrated --out " + dir_ + "/again",
                &log),
            0)
      << log;
  EXPECT_NE(log.find("finished: 60 frames"), std::string::npos) << log;
}

TEST_F(SelfCalibrationCli, ACalibratedRunWritesItsCameraBack) {
  const std::string out = dir_ + "/calibrated";
  std::string log;
  ASSERT_EQ(run("--deterministic --dataset " + dir_ + "/seq --out " + out, &log), 0) << log;
  const GeometricCalibration given = calib::readDsoCameraFile(dir_ + "/seq/camera.txt");
  const GeometricCalibration written = calib::readDsoCameraFile(out + "/camera.txt");
  // Exactly calibrated: nothing leaves its dead band, the file is the given camera.
  EXPECT_EQ(calib::formatDsoCameraFile(written), calib::formatDsoCameraFile(given));
  EXPECT_NE(test::readFile(out + "/camera.txt").find("applied no correction"), std::string::npos);
}

TEST_F(SelfCalibrationCli, BadGuessesAreRefusedNamingTheOption) {
  std::string log;
  EXPECT_NE(run("--fov 5 --dataset " + dir_ + "/uncalibrated --out " + dir_ + "/bad", &log), 0);
  EXPECT_NE(log.find("--fov: 5 is not a horizontal field of view"), std::string::npos) << log;
  EXPECT_NE(run("--fov 80 --calib " + dir_ + "/seq/camera.txt --dataset " + dir_ +
                    "/uncalibrated --out " + dir_ + "/bad",
                &log),
            0);
  EXPECT_NE(log.find("either --calib FILE or --fov DEG"), std::string::npos) << log;
}

// An output folder that is the dataset's own: its camera.txt is never replaced by the refined one.
TEST_F(SelfCalibrationCli, TheCalibrationReadIsNeverOverwritten) {
  std::filesystem::copy(dir_ + "/seq", dir_ + "/inplace", std::filesystem::copy_options::recursive);
  const std::string before = test::readFile(dir_ + "/inplace/camera.txt");
  std::string log;
  EXPECT_NE(run("--deterministic --dataset " + dir_ + "/inplace --out " + dir_ + "/inplace", &log),
            0);
  EXPECT_NE(log.find("camera.txt: not written: it is the calibration this run read"),
            std::string::npos)
      << log;
  EXPECT_EQ(test::readFile(dir_ + "/inplace/camera.txt"), before);
  EXPECT_TRUE(std::filesystem::exists(dir_ + "/inplace/trajectory.txt"));
}

#endif

}  // namespace
}  // namespace ldsm
