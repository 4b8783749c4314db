// describeDataset() and openDataset() on small fixture folders of every image-list layout: the
// decoded frames must be exactly the images written, with the timestamps of the layout's files.
#include "ldsm/drivers/dataset_source.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "dataset_fixtures.h"
#include "ldsm/error.h"

namespace ldsm::drivers {
namespace {

using test::testDir;
using ::testing::EndsWith;

/// Reads every frame; checks pixels against the fixture pattern and the timestamps against
/// `expected_times`. Returns the frames' exposures.
std::vector<double> readAndCheck(FrameSource& source, const std::vector<double>& expected_times) {
  std::vector<double> exposures;
  Frame frame;
  std::size_t k = 0;
  const std::uint8_t* first_buffer = nullptr;
  while (source.next(frame)) {
    EXPECT_EQ(frame.index, static_cast<std::int64_t>(k));
    EXPECT_EQ(frame.image.width(), test::kFixtureWidth);
    EXPECT_EQ(frame.image.height(), test::kFixtureHeight);
    EXPECT_EQ(test::countPatternMismatches(frame.image, static_cast<int>(k)), 0) << "frame " << k;
    if (k < expected_times.size()) {
      EXPECT_NEAR(frame.timestamp, expected_times[k], 1e-6);
    }
    if (k == 0) first_buffer = frame.image.data();
    EXPECT_EQ(frame.image.data(), first_buffer) << "the frame buffer must be reused";
    exposures.push_back(frame.exposure_ms);
    ++k;
  }
  EXPECT_EQ(k, expected_times.size());
  EXPECT_FALSE(source.next(frame)) << "end of stream is sticky";
  return exposures;
}

std::vector<double> uniformTimes(int n, double t0, double dt) {
  std::vector<double> t;
  for (int k = 0; k < n; ++k) t.push_back(t0 + dt * k);
  return t;
}

TEST(DatasetSource, TumMonoImagesFolderWithExposures) {
  const std::string dir = testDir();
  test::writeTumMonoFixture(dir, 5, false);
  const DatasetDescription d = describeDataset(dir);
  EXPECT_EQ(d.format, DatasetFormat::TumMono);
  EXPECT_EQ(d.frame_count, 5);
  EXPECT_EQ(d.width, test::kFixtureWidth);
  EXPECT_EQ(d.height, test::kFixtureHeight);
  EXPECT_TRUE(d.hasExposures());
  EXPECT_FALSE(d.timestamps_assumed);
  EXPECT_NEAR(d.nominal_fps, 20.0, 1e-9);
  EXPECT_THAT(d.timestamps_file, EndsWith("/times.txt"));
  EXPECT_THAT(d.calibration_file, EndsWith("/camera.txt"));
  EXPECT_EQ(d.calibration_kind, CalibrationFileKind::DsoCamera);
  EXPECT_THAT(d.photometric_response_file, EndsWith("/pcalib.txt"));
  EXPECT_THAT(d.vignette_file, EndsWith("/vignette.png"));
  EXPECT_THAT(d.groundtruth_file, EndsWith("/groundtruth.txt"));
  EXPECT_EQ(d.groundtruth_format, TrajectoryFormat::Tum);
  auto source = openDataset(d);
  const SourceInfo info = source->info();
  EXPECT_EQ(info.name, "tum-mono");
  EXPECT_EQ(info.frame_count, 5);
  EXPECT_EQ(info.width, test::kFixtureWidth);
  const auto exposures = readAndCheck(*source, uniformTimes(5, 0.0, 0.05));
  ASSERT_EQ(exposures.size(), 5u);
  for (int k = 0; k < 5; ++k) EXPECT_DOUBLE_EQ(exposures[k], 10.0 + k);
}

TEST(DatasetSource, TumMonoImagesZip) {
  const std::string dir = testDir();
  test::writeTumMonoFixture(dir, 4, true);
  // Rewrite the archive out of order, with a folder entry and a file that is not an image.
  test::writeZip(dir + "/images.zip", {{"00003.png", test::encodePng(test::patternImage(3))},
                                       {"notes.txt", {'h', 'i'}},
                                       {"extra/", {}},
                                       {"00001.png", test::encodePng(test::patternImage(1))},
                                       {"00000.png", test::encodePng(test::patternImage(0))},
                                       {"00002.png", test::encodePng(test::patternImage(2))}});
  const DatasetDescription d = describeDataset(dir);
  EXPECT_EQ(d.format, DatasetFormat::TumMono);
  EXPECT_THAT(d.image_archive, EndsWith("/images.zip"));
  ASSERT_EQ(d.images.size(), 4u);
  EXPECT_EQ(d.images[0], "00000.png");
  auto source = openDataset(d);
  readAndCheck(*source, uniformTimes(4, 0.0, 0.05));
}

TEST(DatasetSource, TumMonoTwoColumnTimesHaveNoExposure) {
  const std::string dir = testDir();
  test::writeTumMonoFixture(dir, 3, false);
  test::writeText(dir + "/times.txt", "00000 0.0\n00001 0.5\n00002 1.0\n");
  const DatasetDescription d = describeDataset(dir, DatasetFormat::TumMono);
  EXPECT_FALSE(d.hasExposures());
  auto source = openDataset(d);
  for (double e : readAndCheck(*source, {0.0, 0.5, 1.0})) EXPECT_TRUE(std::isnan(e));
}

TEST(DatasetSource, EurocNanosecondTimestamps) {
  const std::string dir = testDir();
  test::writeEurocFixture(dir, 4);
  const DatasetDescription d = describeDataset(dir);
  EXPECT_EQ(d.format, DatasetFormat::Euroc);
  EXPECT_EQ(d.calibration_kind, CalibrationFileKind::CameraYaml);
  EXPECT_THAT(d.calibration_file, EndsWith("mav0/cam0/sensor.yaml"));
  EXPECT_TRUE(d.groundtruth_file.empty());
  auto source = openDataset(dir);
  readAndCheck(*source, uniformTimes(4, 1403715273.0, 0.05));
}

TEST(DatasetSource, EurocGroundTruthCsv) {
  const std::string dir = testDir();
  test::writeEurocFixture(dir, 2);
  test::writeText(dir + "/mav0/state_groundtruth_estimate0/data.csv",
                  "#timestamp,p_x,p_y,p_z,q_w,q_x,q_y,q_z\n1403715273000000000,0,0,0,1,0,0,0\n");
  const DatasetDescription d = describeDataset(dir + "/mav0");
  EXPECT_THAT(d.groundtruth_file, EndsWith("state_groundtruth_estimate0/data.csv"));
  EXPECT_EQ(d.groundtruth_format, TrajectoryFormat::EurocCsv);
}

TEST(DatasetSource, KittiFromRootAndFromSequence) {
  const std::string dir = testDir();
  test::writeKittiFixture(dir, 3);
  for (const std::string& path : {dir, dir + "/sequences/04", dir + "/sequences/04/"}) {
    SCOPED_TRACE(path);
    const DatasetDescription d = describeDataset(path);
    EXPECT_EQ(d.format, DatasetFormat::Kitti);
    EXPECT_EQ(d.calibration_kind, CalibrationFileKind::KittiCalib);
    EXPECT_EQ(d.calibration_camera, 0);
    EXPECT_THAT(d.groundtruth_file, EndsWith("poses/04.txt"));
    EXPECT_EQ(d.groundtruth_format, TrajectoryFormat::Kitti);
    auto source = openDataset(d);
    readAndCheck(*source, uniformTimes(3, 0.0, 0.1));
  }
}

TEST(DatasetSource, KittiSeveralSequencesNeedsOne) {
  const std::string dir = testDir();
  test::writeKittiFixture(dir, 2);
  std::filesystem::create_directories(dir + "/sequences/05/image_0");
  try {
    describeDataset(dir);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("04, 05"));
  }
}

TEST(DatasetSource, TumRgbdColourImagesBecomeGrey) {
  const std::string dir = testDir();
  test::writeTumRgbdFixture(dir, 3);
  const DatasetDescription d = describeDataset(dir);
  EXPECT_EQ(d.format, DatasetFormat::TumRgbd);
  EXPECT_EQ(d.calibration_kind, CalibrationFileKind::None);
  auto source = openDataset(d);
  readAndCheck(*source, uniformTimes(3, 1305031102.0, 0.033));
}

TEST(DatasetSource, FolderInNaturalOrderAtAssumedRate) {
  const std::string dir = testDir();
  // Written out of order, with names whose byte order differs from their numeric order.
  for (int k : {10, 2, 1, 0})
    test::writeImage(dir + "/" + std::to_string(k) + ".png", test::patternImage(k == 10 ? 3 : k));
  test::writeText(dir + "/notes.txt", "not an image\n");
  const DatasetDescription d = describeDataset(dir);
  EXPECT_EQ(d.format, DatasetFormat::Folder);
  EXPECT_TRUE(d.timestamps_assumed);
  EXPECT_EQ(d.frame_count, 4);
  EXPECT_DOUBLE_EQ(d.nominal_fps, kAssumedFolderFps);
  auto source = openDataset(d);
  readAndCheck(*source, uniformTimes(4, 0.0, 1.0 / kAssumedFolderFps));
}

TEST(DatasetSource, SixteenBitImagesAreScaledToEightBit) {
  const std::string dir = testDir();
  cv::Mat deep(test::kFixtureHeight, test::kFixtureWidth, CV_16U);
  for (int y = 0; y < deep.rows; ++y)
    for (int x = 0; x < deep.cols; ++x)
      deep.at<std::uint16_t>(y, x) = static_cast<std::uint16_t>(
          256 * test::patternValue(0, x, y) + (x % 2 == 0 ? 40 : 0));  // never a .5 fraction
  test::writeImage(dir + "/0.png", deep);
  auto source = openDataset(dir, DatasetFormat::Folder);
  Frame frame;
  ASSERT_TRUE(source->next(frame));
  EXPECT_EQ(test::countPatternMismatches(frame.image, 0), 0);
}

TEST(DatasetSource, DescriptionWithoutFormatIsRejected) {
  DatasetDescription d;
  d.root = "somewhere";
  EXPECT_THROW(openDataset(d), InputError);
}

}  // namespace
}  // namespace ldsm::drivers
