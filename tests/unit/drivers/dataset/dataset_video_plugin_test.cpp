// The video plugin is loaded on demand: found through LDSM_PLUGIN_PATH or the default folders,
// and its absence is a clear input error, not a crash.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <functional>
#include <optional>
#include <string>

#include <opencv2/videoio.hpp>

#include "dataset_fixtures.h"
#include "ldsm/drivers/dataset_source.h"
#include "ldsm/error.h"

namespace ldsm::drivers {
namespace {

using ::testing::HasSubstr;
using ::testing::StartsWith;

/// Sets LDSM_PLUGIN_PATH for the lifetime of the object, then restores it.
class ScopedPluginPath {
 public:
  explicit ScopedPluginPath(const std::string& value) {
    if (const char* old = std::getenv("LDSM_PLUGIN_PATH")) old_ = old;
    setenv("LDSM_PLUGIN_PATH", value.c_str(), 1);
  }
  ~ScopedPluginPath() {
    if (old_) {
      setenv("LDSM_PLUGIN_PATH", old_->c_str(), 1);
    } else {
      unsetenv("LDSM_PLUGIN_PATH");
    }
  }

 private:
  std::optional<std::string> old_;
};

std::string inputErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no ldsm::InputError";
  return {};
}

bool writeClip(const std::string& path) {
  cv::VideoWriter writer(path, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 10.0, cv::Size(32, 24),
                         true);
  if (!writer.isOpened()) return false;
  for (int k = 0; k < 3; ++k) writer.write(cv::Mat(24, 32, CV_8UC3, cv::Scalar::all(60 * k)));
  return true;
}

TEST(DatasetVideoPlugin, MissingPluginIsAClearInputError) {
  const std::string dir = test::testDir();
  const std::string video = dir + "/clip.avi";
  test::writeText(video, "any bytes: the plugin is looked for before the file is read");
  const ScopedPluginPath env(dir + "/no_plugins_here:" + dir + "/nor_here");
  const std::string error = inputErrorOf([&] { describeDataset(video); });
  EXPECT_THAT(error, StartsWith(video +
                                ": cannot read video: the video plugin "
                                "libldsm_video_plugin.so was not found (searched: " +
                                dir + "/no_plugins_here, " + dir + "/nor_here)"));
  EXPECT_THAT(error, HasSubstr("LDSM_PLUGIN_PATH"));
  DatasetDescription d;
  d.format = DatasetFormat::Video;
  d.root = video;
  EXPECT_THAT(inputErrorOf([&] { openDataset(d); }), HasSubstr("was not found"));
}

TEST(DatasetVideoPlugin, AFileThatIsNotAPluginIsRefused) {
  const std::string dir = test::testDir();
  test::writeText(dir + "/plugins/libldsm_video_plugin.so", "not a shared object");
  test::writeText(dir + "/clip.avi", "x");
  const ScopedPluginPath env(dir + "/plugins");
  EXPECT_THAT(inputErrorOf([&] { describeDataset(dir + "/clip.avi"); }),
              HasSubstr("cannot load the video plugin"));
}

#ifdef LDSM_VIDEO_PLUGIN_DIR
TEST(DatasetVideoPlugin, FoundThroughLdsmPluginPath) {
  const std::string dir = test::testDir();
  const std::string video = dir + "/clip.avi";
  if (!writeClip(video)) GTEST_SKIP() << "OpenCV has no MJPEG video writer";
  const ScopedPluginPath env(std::string("/nonexistent:") + LDSM_VIDEO_PLUGIN_DIR);
  auto source = openDataset(video);
  Frame frame;
  int n = 0;
  while (source->next(frame)) ++n;
  EXPECT_EQ(n, 3);
}
#endif

TEST(DatasetVideoPlugin, CorruptVideoIsAnInputError) {
  const std::string dir = test::testDir();
  test::writeText(dir + "/junk.avi", "RIFF but not really a video file at all");
  EXPECT_THAT(inputErrorOf([&] { describeDataset(dir + "/junk.avi"); }),
              StartsWith(dir + "/junk.avi: "));
}

}  // namespace
}  // namespace ldsm::drivers
