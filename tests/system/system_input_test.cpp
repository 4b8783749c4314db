// Bad input to the System and to `ldsm run`: clear errors, no crash, results so far kept.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <limits>

#include "ldsm/drivers/sim/sim_source.h"
#include "ldsm/error.h"
#include "ldsm/system.h"
#include "test_paths.h"

namespace ldsm {
namespace {

GeometricCalibration smallCamera(int w = 160, int h = 120) {
  GeometricCalibration g;
  g.input = {CameraModelType::Pinhole, 120.0, 120.0, (w - 1) / 2.0, (h - 1) / 2.0, {}, w, h};
  g.output.mode = OutputMode::None;
  g.output.width = w;
  g.output.height = h;
  return g;
}

ImageU8 texturedImage(int w, int h, int shift = 0) {
  ImageU8 img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      img(x, y) =
          static_cast<std::uint8_t>(128 + 60 * std::sin(0.21 * (x + shift)) * std::cos(0.17 * y));
  return img;
}

Config deterministic() {
  Config c;
  c.system.deterministic = true;
  return c;
}

TEST(SystemInput, WrongImageSizeThrowsNamingBothSizes) {
  System system(deterministic(), smallCamera());
  const ImageU8 img = texturedImage(100, 80);
  try {
    system.submit({img.view(), 0.0});
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("100x80"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("160x120"), std::string::npos) << e.what();
  }
}

TEST(SystemInput, BadFramesAreRejectedAndCounted) {
  System system(deterministic(), smallCamera());
  const ImageU8 good = texturedImage(160, 120);
  ImageU8 black(160, 120, 0), saturated(160, 120, 255);
  system.submit({good.view(), 1.0});
  system.submit({good.view(), 1.0});  // duplicated timestamp
  system.submit({good.view(), 0.5});  // backwards
  system.submit({good.view(), std::numeric_limits<double>::quiet_NaN()});
  system.submit({good.view(), 2.0, 0.0});   // zero exposure
  system.submit({good.view(), 3.0, -1.0});  // negative exposure
  system.submit({black.view(), 4.0});
  system.submit({saturated.view(), 5.0});
  system.submit({good.view(), 6.0});
  const SystemStats s = system.stats();
  EXPECT_EQ(s.frames, 9);
  EXPECT_EQ(s.rejected_frames, 7);
  EXPECT_NO_THROW(system.finish());
}

TEST(SystemInput, MissingExposureAfterKnownOnesIsRejected) {
  System system(deterministic(), smallCamera());
  const ImageU8 good = texturedImage(160, 120);
  system.submit({good.view(), 1.0, 10.0});
  system.submit({good.view(), 2.0});  // NaN exposure
  EXPECT_EQ(system.stats().rejected_frames, 1);
}

TEST(SystemInput, TooShortSequenceStaysInitializingWithoutPoses) {
  System system(deterministic(), smallCamera());
  for (int i = 0; i < 4; ++i) {
    const ImageU8 img = texturedImage(160, 120, i);
    system.submit({img.view(), 0.1 * i});
  }
  system.finish();
  EXPECT_EQ(system.status(), TrackingStatus::Initializing);
  EXPECT_TRUE(system.trajectory().empty());
  EXPECT_TRUE(system.keyframeTrajectory().empty());
}

TEST(SystemInput, InvalidConfigurationNamesTheKey) {
  Config c = deterministic();
  c.window.max_keyframes = 1;
  try {
    System system(c, smallCamera());
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("window.max_keyframes"), std::string::npos);
  }
}

TEST(SystemInput, NanInCalibrationIsAnInputError) {
  GeometricCalibration g = smallCamera();
  g.input.fx = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(System(deterministic(), g), InputError);
}

TEST(RunCommand, UnreadableFrameMidSequenceKeepsTheTrajectorySoFar) {
  const std::string dir = test::scratchDir("run_corrupt");
  std::string out;
  ASSERT_EQ(
      test::runCommand(std::string(LDSM_EXE) + " sim --scene short --out " + dir + "/scene", &out),
      0)
      << out;
  // Corrupt a late frame: the run must stop there with a clear message, keeping what it did.
  std::vector<std::filesystem::path> images;
  for (const auto& e : std::filesystem::directory_iterator(dir + "/scene/images"))
    images.push_back(e.path());
  std::sort(images.begin(), images.end());
  ASSERT_GT(images.size(), 40u);
  const auto bad = images[images.size() - 5];
  std::ofstream(bad, std::ios::trunc) << "not a png";
  const int rc = test::runCommand(std::string(LDSM_EXE) + " run --deterministic --dataset " + dir +
                                      "/scene --out " + dir + "/result",
                                  &out);
  EXPECT_EQ(rc, 1) << out;
  EXPECT_NE(out.find(bad.filename().string()), std::string::npos) << out;
  std::ifstream traj(dir + "/result/trajectory.txt");
  ASSERT_TRUE(traj.good());
  int lines = 0;
  for (std::string l; std::getline(traj, l);) lines += (!l.empty() && l[0] != '#') ? 1 : 0;
  EXPECT_GT(lines, 10);
  EXPECT_TRUE(std::filesystem::exists(dir + "/result/stats.json"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/result/points.ply"));
}

TEST(RunCommand, MissingDatasetIsAClearError) {
  std::string out;
  EXPECT_EQ(test::runCommand(std::string(LDSM_EXE) + " run --dataset /nonexistent/seq", &out), 1);
  EXPECT_NE(out.find("/nonexistent/seq"), std::string::npos) << out;
}

}  // namespace
}  // namespace ldsm
