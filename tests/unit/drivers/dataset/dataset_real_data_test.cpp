// The real sequences of ../shared/data: layout, counts, time span, image size, and the first frame
// decoded exactly as OpenCV reads the file in grey.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "dataset_fixtures.h"
#include "ldsm/drivers/dataset_source.h"

namespace ldsm::drivers {
namespace {

using ::testing::EndsWith;

struct RealSequence {
  const char* folder;  ///< below ../shared/data
  DatasetFormat format;
  std::int64_t frames;
  int width, height;
  double first_t, last_t;   ///< seconds, as written in the sequence's timestamp file
  const char* calibration;  ///< expected calibration file name ("" = none)
  const char* groundtruth;  ///< expected ground-truth file name ("" = none)
};

class RealData : public ::testing::TestWithParam<RealSequence> {};

TEST_P(RealData, DescribesAndDecodesFirstFrame) {
  const RealSequence& s = GetParam();
  const std::string path = test::sharedData(s.folder);
  if (path.empty()) GTEST_SKIP() << "../shared/data absent: " << s.folder;

  EXPECT_EQ(detectDatasetFormat(path), s.format);
  const DatasetDescription d = describeDataset(path);
  EXPECT_EQ(d.format, s.format);
  EXPECT_EQ(d.frame_count, s.frames);
  EXPECT_EQ(static_cast<std::int64_t>(d.images.size()), s.frames);
  EXPECT_EQ(d.width, s.width);
  EXPECT_EQ(d.height, s.height);
  ASSERT_EQ(static_cast<std::int64_t>(d.timestamps.size()), s.frames);
  EXPECT_NEAR(d.firstTimestamp(), s.first_t, 1e-6);
  EXPECT_NEAR(d.lastTimestamp(), s.last_t, 1e-6);
  EXPECT_FALSE(d.hasExposures());
  if (*s.calibration != '\0') {
    EXPECT_THAT(d.calibration_file, EndsWith(s.calibration));
  } else {
    EXPECT_EQ(d.calibration_kind, CalibrationFileKind::None);
  }
  if (*s.groundtruth != '\0') {
    EXPECT_THAT(d.groundtruth_file, EndsWith(s.groundtruth));
  } else {
    EXPECT_TRUE(d.groundtruth_file.empty());
  }

  auto source = openDataset(d);
  EXPECT_EQ(source->info().frame_count, s.frames);
  Frame frame;
  ASSERT_TRUE(source->next(frame));
  EXPECT_EQ(frame.index, 0);
  EXPECT_NEAR(frame.timestamp, s.first_t, 1e-6);
  ASSERT_EQ(frame.image.width(), s.width);
  ASSERT_EQ(frame.image.height(), s.height);
  const cv::Mat expected = cv::imread(d.images.front(), cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(expected.empty());
  int mismatches = 0;
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x)
      mismatches += frame.image(x, y) != expected.at<unsigned char>(y, x) ? 1 : 0;
  EXPECT_EQ(mismatches, 0);
  ASSERT_TRUE(source->next(frame));
  EXPECT_EQ(frame.index, 1);
  EXPECT_GT(frame.timestamp, s.first_t);
}

INSTANTIATE_TEST_SUITE_P(
    SharedData, RealData,
    ::testing::Values(
        RealSequence{"kitti00_200", DatasetFormat::Kitti, 200, 1241, 376, 0.0, 20.63096,
                     "kitti00_200/camera.txt", "kitti00_200/groundtruth.txt"},
        RealSequence{"vamr_desk_loop", DatasetFormat::TumMono, 736, 752, 480, 0.0, 24.5,
                     "vamr_desk_loop/camera.txt", "vamr_desk_loop/groundtruth.txt"},
        RealSequence{"euroc_v101_static95", DatasetFormat::Euroc, 95, 752, 480,
                     1403715273.262142976, 1403715277.962142976, "euroc_v101_static95/camera.txt",
                     "euroc_v101_static95/groundtruth_body.txt"},
        RealSequence{"rtabmap_loop84/samples", DatasetFormat::Folder, 84, 512, 384, 0.0,
                     83.0 / kAssumedFolderFps, "", ""},
        // The top folder: images in samples/, the ground-truth bitmap beside them.
        RealSequence{"rtabmap_loop84", DatasetFormat::Folder, 84, 512, 384, 0.0,
                     83.0 / kAssumedFolderFps, "", ""}),
    [](const ::testing::TestParamInfo<RealSequence>& param_info) {
      std::string name = param_info.param.folder;
      for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
      return name;
    });

TEST(RealDataFolder, RtabmapSamplesAreInNaturalOrder) {
  const std::string path = test::sharedData("rtabmap_loop84/samples");
  if (path.empty()) GTEST_SKIP() << "../shared/data absent: rtabmap_loop84/samples";
  const DatasetDescription d = describeDataset(path);
  ASSERT_EQ(d.images.size(), 84u);
  for (std::size_t i = 0; i < d.images.size(); ++i) {
    EXPECT_THAT(d.images[i], EndsWith("/" + std::to_string(i + 1) + ".jpg"));
  }
}

}  // namespace
}  // namespace ldsm::drivers
