// Bad dataset input: every case throws ldsm::InputError whose message names the file at fault
// (and the line for text files), and never yields garbage frames.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <functional>

#include "dataset_fixtures.h"
#include "ldsm/drivers/dataset_source.h"
#include "ldsm/error.h"

namespace ldsm::drivers {
namespace {

using test::testDir;
using ::testing::HasSubstr;
using ::testing::StartsWith;

/// The message of the InputError `f` throws ("" and a test failure when it throws none).
std::string inputErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not an InputError: " << e.what();
    return {};
  }
  ADD_FAILURE() << "no exception";
  return {};
}

/// Reads every frame of `path` (the error may come from describe or from decoding).
void readAll(const std::string& path, DatasetFormat format = DatasetFormat::Auto) {
  auto source = openDataset(path, format);
  Frame frame;
  while (source->next(frame)) {
  }
}

TEST(DatasetBadInput, MissingFolder) {
  const std::string missing = testDir() + "/nope";
  EXPECT_EQ(inputErrorOf([&] { describeDataset(missing); }),
            missing + ": no such file or directory");
  EXPECT_EQ(inputErrorOf([&] { describeDataset(missing, DatasetFormat::Kitti); }),
            missing + ": no such file or directory");
}

TEST(DatasetBadInput, UnknownLayout) {
  const std::string dir = testDir();
  test::writeText(dir + "/readme.md", "hello\n");
  EXPECT_THAT(inputErrorOf([&] { describeDataset(dir); }),
              StartsWith(dir + ": unknown dataset layout"));
}

TEST(DatasetBadInput, ForcedFormatOnWrongLayoutNamesTheMissingFile) {
  const std::string dir = testDir();
  test::writeKittiFixture(dir, 2);
  EXPECT_THAT(inputErrorOf([&] { describeDataset(dir, DatasetFormat::TumMono); }),
              StartsWith(dir + "/times.txt: no such file"));
  EXPECT_THAT(inputErrorOf([&] { describeDataset(dir, DatasetFormat::TumRgbd); }),
              StartsWith(dir + "/rgb.txt: no such file"));
  EXPECT_THAT(inputErrorOf([&] { describeDataset(dir, DatasetFormat::Euroc); }),
              HasSubstr("data.csv: no such file"));
}

TEST(DatasetBadInput, MalformedTumMonoTimesLine) {
  const std::string dir = testDir();
  test::writeTumMonoFixture(dir, 3, false);
  const std::string times = dir + "/times.txt";
  test::writeText(times, "00000 0.0 10\n00001 0.1x 10\n00002 0.2 10\n");
  EXPECT_THAT(inputErrorOf([&] { describeDataset(dir); }), StartsWith(times + ":2: "));
  test::writeText(times, "00000 0.0 10\n\n00001 0.1 10 7\n00002 0.2 10\n");
  EXPECT_THAT(inputErrorOf([&] { describeDataset(dir); }), StartsWith(times + ":3: "));
  test::writeText(times, "00000 0.0 10\n00001 0.1 -3\n00002 0.2 10\n");
  EXPECT_THAT(inputErrorOf([&] { describeDataset(dir); }), StartsWith(times + ":2: exposure"));
  test::writeText(times, "00000 0.0 10\n00001 nan 10\n00002 0.2 10\n");
  EXPECT_THAT(inputErrorOf([&] { describeDataset(dir); }), StartsWith(times + ":2: "));
  test::writeText(times, "x 0.0\n00001 0.1\n00002 0.2\n");
  EXPECT_THAT(inputErrorOf([&] { describeDataset(dir); }), StartsWith(times + ":1: frame id"));
}

TEST(DatasetBadInput, MalformedKittiEurocAndRgbdLines) {
  const std::string dir = testDir();
  test::writeKittiFixture(dir + "/kitti", 2);
  const std::string ktimes = dir + "/kitti/sequences/04/times.txt";
  test::writeText(ktimes, "0.0\n0.1 0.2\n");
  EXPECT_THAT(inputErrorOf([&] { describeDataset(dir + "/kitti"); }), StartsWith(ktimes + ":2: "));

  test::writeEurocFixture(dir + "/euroc", 2);
  const std::string csv = dir + "/euroc/mav0/cam0/data.csv";
  test::writeText(csv, "#timestamp [ns],filename\n1.5,a.png\n");
  EXPECT_THAT(inputErrorOf([&] { describeDataset(dir + "/euroc"); }), StartsWith(csv + ":2: "));
  test::writeText(csv, "#timestamp [ns],filename\n100\n");
  EXPECT_THAT(inputErrorOf([&] { describeDataset(dir + "/euroc"); }), StartsWith(csv + ":2: "));

  test::writeTumRgbdFixture(dir + "/rgbd", 2);
  const std::string list = dir + "/rgbd/rgb.txt";
  test::writeText(list, "# comment\n1.0 rgb/a.png extra\n");
  EXPECT_THAT(inputErrorOf([&] { describeDataset(dir + "/rgbd"); }), StartsWith(list + ":2: "));
}

TEST(DatasetBadInput, ListedImageMissing) {
  const std::string dir = testDir();
  test::writeEurocFixture(dir, 2);
  const std::string csv = dir + "/mav0/cam0/data.csv";
  test::writeText(csv,
                  "#timestamp [ns],filename\n1403715273000000000,1403715273000000000.png\n"
                  "1403715273050000000,missing.png\n");
  EXPECT_THAT(inputErrorOf([&] { describeDataset(dir); }),
              AllOf(StartsWith(csv + ":3: "), HasSubstr("missing.png")));
}

TEST(DatasetBadInput, BackwardsAndDuplicatedTimestamps) {
  const std::string dir = testDir();
  test::writeTumMonoFixture(dir, 3, false);
  const std::string times = dir + "/times.txt";
  test::writeText(times, "00000 0.0\n00001 0.2\n00002 0.1\n");
  EXPECT_THAT(inputErrorOf([&] { describeDataset(dir); }),
              AllOf(StartsWith(times + ":3: "), HasSubstr("non-monotonic")));
  test::writeText(times, "00000 0.0\n00001 0.2\n00002 0.2\n");
  EXPECT_THAT(inputErrorOf([&] { describeDataset(dir); }),
              AllOf(StartsWith(times + ":3: "), HasSubstr("duplicated")));
}

TEST(DatasetBadInput, ImageCountDiffersFromTimestampCount) {
  const std::string dir = testDir();
  test::writeTumMonoFixture(dir, 3, false);
  const std::string times = dir + "/times.txt";
  test::writeText(times, "00000 0.0\n00001 0.1\n");
  EXPECT_THAT(inputErrorOf([&] { describeDataset(dir); }),
              AllOf(StartsWith(times + ": 2 timestamps"), HasSubstr("3 images")));

  test::writeKittiFixture(dir + "/kitti", 3);
  std::filesystem::remove(dir + "/kitti/sequences/04/image_0/000002.png");
  EXPECT_THAT(inputErrorOf([&] { describeDataset(dir + "/kitti"); }),
              AllOf(HasSubstr("04/times.txt: 3 timestamps"), HasSubstr("2 images")));
}

TEST(DatasetBadInput, ImageOfADifferentSize) {
  const std::string dir = testDir();
  test::writeKittiFixture(dir, 3);
  const std::string odd = dir + "/sequences/04/image_0/000001.png";
  test::writeImage(odd, test::patternImage(1, test::kFixtureWidth + 2, test::kFixtureHeight));
  auto source = openDataset(dir);
  Frame frame;
  ASSERT_TRUE(source->next(frame));
  EXPECT_THAT(inputErrorOf([&] { source->next(frame); }),
              AllOf(StartsWith(odd + ": "), HasSubstr("26x16"), HasSubstr("24x16")));
  EXPECT_FALSE(source->next(frame)) << "after an error the source is at end of stream";
}

TEST(DatasetBadInput, UnreadableImage) {
  const std::string dir = testDir();
  test::writeTumMonoFixture(dir, 3, false);
  const std::string broken = dir + "/images/00002.png";
  test::writeText(broken, "this is not a PNG file");
  EXPECT_THAT(inputErrorOf([&] { readAll(dir); }), StartsWith(broken + ": cannot decode"));
  const std::string empty = dir + "/images/00000.png";
  test::writeText(empty, "");
  EXPECT_THAT(inputErrorOf([&] { describeDataset(dir); }), StartsWith(empty + ": cannot decode"));
}

TEST(DatasetBadInput, UnreadableZipEntryAndBadArchive) {
  const std::string dir = testDir();
  test::writeTumMonoFixture(dir, 2, true);
  test::writeZip(dir + "/images.zip",
                 {{"00000.png", test::encodePng(test::patternImage(0))},
                  {"00001.png", std::vector<unsigned char>{'j', 'u', 'n', 'k'}}});
  EXPECT_THAT(inputErrorOf([&] { readAll(dir); }),
              StartsWith(dir + "/images.zip:00001.png: cannot decode"));
  test::writeText(dir + "/images.zip", "not a zip");
  EXPECT_THAT(inputErrorOf([&] { describeDataset(dir); }), StartsWith(dir + "/images.zip: "));
}

TEST(DatasetBadInput, EmptyDataset) {
  const std::string dir = testDir();
  test::writeText(dir + "/times.txt", "# no frames\n");
  std::filesystem::create_directories(dir + "/images");
  EXPECT_THAT(inputErrorOf([&] { describeDataset(dir); }),
              AllOf(StartsWith(dir + ": "), HasSubstr("no images")));
}

TEST(DatasetBadInput, VideoThatIsNotAVideo) {
  const std::string dir = testDir();
  test::writeText(dir + "/clip.avi", "garbage bytes, not a container");
  EXPECT_THAT(inputErrorOf([&] { describeDataset(dir + "/clip.avi"); }),
              StartsWith(dir + "/clip.avi: "));
}

}  // namespace
}  // namespace ldsm::drivers
