// Dataset format names and layout detection.
#include "ldsm/drivers/dataset_format.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "dataset_fixtures.h"
#include "ldsm/error.h"

namespace ldsm::drivers {
namespace {

using test::testDir;
using ::testing::HasSubstr;

TEST(DatasetFormatName, RoundTripsEveryFormat) {
  for (auto f :
       {DatasetFormat::Auto, DatasetFormat::TumMono, DatasetFormat::Euroc, DatasetFormat::Kitti,
        DatasetFormat::TumRgbd, DatasetFormat::Folder, DatasetFormat::Video}) {
    EXPECT_EQ(parseDatasetFormat(toString(f)), f) << toString(f);
  }
  EXPECT_STREQ(toString(DatasetFormat::TumMono), "tum-mono");
  EXPECT_STREQ(toString(DatasetFormat::TumRgbd), "tum-rgbd");
}

TEST(DatasetFormatName, UnknownNameListsAcceptedNames) {
  try {
    parseDatasetFormat("tum_mono");
    FAIL() << "no exception";
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), HasSubstr("tum_mono"));
    EXPECT_THAT(e.what(), HasSubstr("tum-mono"));
    EXPECT_THAT(e.what(), HasSubstr("euroc"));
  }
}

TEST(DatasetFormatName, Extensions) {
  EXPECT_TRUE(hasImageExtension("a/b/00001.PNG"));
  EXPECT_TRUE(hasImageExtension("x.jpeg"));
  EXPECT_FALSE(hasImageExtension("times.txt"));
  EXPECT_FALSE(hasImageExtension("png"));
  EXPECT_TRUE(hasVideoExtension("run.MP4"));
  EXPECT_FALSE(hasVideoExtension("run.png"));
}

TEST(DetectDatasetFormat, TumMonoFolderAndZip) {
  const std::string dir = testDir();
  test::writeTumMonoFixture(dir + "/folder", 2, false);
  test::writeTumMonoFixture(dir + "/zip", 2, true);
  EXPECT_EQ(detectDatasetFormat(dir + "/folder"), DatasetFormat::TumMono);
  EXPECT_EQ(detectDatasetFormat(dir + "/zip"), DatasetFormat::TumMono);
}

TEST(DetectDatasetFormat, EurocAtRootAndAtMav0) {
  const std::string dir = testDir();
  test::writeEurocFixture(dir, 2);
  EXPECT_EQ(detectDatasetFormat(dir), DatasetFormat::Euroc);
  EXPECT_EQ(detectDatasetFormat(dir + "/mav0"), DatasetFormat::Euroc);
}

TEST(DetectDatasetFormat, KittiRootAndSequenceFolder) {
  const std::string dir = testDir();
  test::writeKittiFixture(dir, 2);
  EXPECT_EQ(detectDatasetFormat(dir), DatasetFormat::Kitti);
  EXPECT_EQ(detectDatasetFormat(dir + "/sequences/04"), DatasetFormat::Kitti);
}

TEST(DetectDatasetFormat, TumRgbdAndFolder) {
  const std::string dir = testDir();
  test::writeTumRgbdFixture(dir + "/rgbd", 2);
  EXPECT_EQ(detectDatasetFormat(dir + "/rgbd"), DatasetFormat::TumRgbd);
  EXPECT_EQ(detectDatasetFormat(dir + "/rgbd/rgb"), DatasetFormat::Folder);
}

TEST(DetectDatasetFormat, VideoFileByExtension) {
  const std::string dir = testDir();
  test::writeText(dir + "/clip.mp4", "not really a video");
  EXPECT_EQ(detectDatasetFormat(dir + "/clip.mp4"), DatasetFormat::Video);
}

TEST(DetectDatasetFormat, MissingPathSaysNoSuchFile) {
  const std::string missing = testDir() + "/does_not_exist";
  try {
    detectDatasetFormat(missing);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), missing + ": no such file or directory");
  }
}

TEST(DetectDatasetFormat, UnknownLayoutListsWhatWasLookedFor) {
  const std::string dir = testDir();
  test::writeText(dir + "/notes.txt", "nothing here\n");
  test::writeText(dir + "/times.txt", "0 0.0\n");  // times.txt without images/ is not TUM-Mono
  try {
    detectDatasetFormat(dir);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr(dir + ": unknown dataset layout"));
    EXPECT_THAT(e.what(), HasSubstr("mav0/cam0/data.csv"));
    EXPECT_THAT(e.what(), HasSubstr("image_0"));
    EXPECT_THAT(e.what(), HasSubstr("rgb.txt"));
    EXPECT_THAT(e.what(), HasSubstr("images.zip"));
  }
}

TEST(DetectDatasetFormat, NonVideoFileIsRejected) {
  const std::string dir = testDir();
  test::writeText(dir + "/times.txt", "0 0.0\n");
  EXPECT_THROW(detectDatasetFormat(dir + "/times.txt"), InputError);
}

}  // namespace
}  // namespace ldsm::drivers
