// Video files: a small MJPEG AVI written here with OpenCV, read back through openDataset().
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <opencv2/videoio.hpp>

#include "dataset_fixtures.h"
#include "ldsm/drivers/dataset_source.h"

namespace ldsm::drivers {
namespace {

constexpr int kFrames = 6;
constexpr double kFps = 10.0;

/// Writes kFrames flat frames of grey level 40 + 30 k; returns false when no MJPEG writer exists.
bool writeVideo(const std::string& path) {
  cv::VideoWriter writer(path, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), kFps, cv::Size(64, 48),
                         true);
  if (!writer.isOpened()) return false;
  for (int k = 0; k < kFrames; ++k) {
    writer.write(cv::Mat(48, 64, CV_8UC3, cv::Scalar::all(40 + 30 * k)));
  }
  return true;
}

double meanOf(const ImageU8& image) {
  double sum = 0;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) sum += image(x, y);
  return sum / static_cast<double>(image.size());
}

TEST(DatasetVideo, ReadsFramesWithTimestampsFromTheFrameRate) {
  const std::string path = test::testDir() + "/clip.avi";
  if (!writeVideo(path)) GTEST_SKIP() << "OpenCV has no MJPEG video writer";
  const DatasetDescription d = describeDataset(path);
  EXPECT_EQ(d.format, DatasetFormat::Video);
  EXPECT_EQ(d.width, 64);
  EXPECT_EQ(d.height, 48);
  EXPECT_NEAR(d.nominal_fps, kFps, 1e-6);
  EXPECT_EQ(d.frame_count, kFrames);

  auto source = openDataset(d);
  EXPECT_EQ(source->info().name, "video");
  Frame frame;
  int k = 0;
  while (source->next(frame)) {
    EXPECT_EQ(frame.index, k);
    EXPECT_NEAR(frame.timestamp, k / kFps, 1e-3) << "frame " << k;
    EXPECT_TRUE(std::isnan(frame.exposure_ms));
    ASSERT_EQ(frame.image.width(), 64);
    ASSERT_EQ(frame.image.height(), 48);
    EXPECT_NEAR(meanOf(frame.image), 40 + 30 * k, 3.0) << "frame " << k;
    ++k;
  }
  EXPECT_EQ(k, kFrames);
  EXPECT_FALSE(source->next(frame));
}

}  // namespace
}  // namespace ldsm::drivers
