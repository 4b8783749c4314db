// TrajectorySpill: the frame poses a long run hands out (System::takeRetiredFrames()) kept on disk
// exactly as they were, read back in order before the poses still in memory; a failed write
// names the file and loses nothing.
#include "ldsm/drivers/trajectory_spill.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "ldsm/error.h"

namespace ldsm::drivers {
namespace {

Trajectory poses(int from, int count, int map = 0) {
  Trajectory t;
  for (int i = from; i < from + count; ++i) {
    StampedPose p;
    p.timestamp = 1e9 + i / 3.0;
    p.pose.translation = {std::sin(i), 1.0 / (i + 1), -i * 1e-7};
    p.pose.rotation =
        Eigen::Quaterniond(Eigen::AngleAxisd(0.01 * i, Eigen::Vector3d(1, 2, 3).normalized()));
    p.map = map;
    t.push_back(p);
  }
  return t;
}

void expectSame(const StampedPose& a, const StampedPose& b) {
  EXPECT_EQ(a.timestamp, b.timestamp);
  EXPECT_EQ(a.pose.translation, b.pose.translation);
  EXPECT_EQ(a.pose.rotation.coeffs(), b.pose.rotation.coeffs());
  EXPECT_EQ(a.map, b.map);
}

TEST(TrajectorySpill, KeepsEveryPoseExactlyAndInOrder) {
  const std::string dir =
      (std::filesystem::temp_directory_path() / ("ldsm-spill-test-" + std::to_string(::getpid())))
          .string();
  const std::string path = dir + "/sub/retired.bin";  // folders made when needed
  TrajectorySpill spill(path);
  EXPECT_TRUE(spill.read().empty());
  EXPECT_FALSE(std::filesystem::exists(path));  // nothing to keep yet
  spill.append(poses(0, 1000));
  spill.append({});
  spill.append(poses(1000, 500, 2));
  EXPECT_EQ(spill.size(), 1500);
  const Trajectory all = spill.read(poses(1500, 10));
  ASSERT_EQ(all.size(), 1510u);
  const Trajectory expected = [] {
    Trajectory t = poses(0, 1000);
    for (const auto& p : poses(1000, 500, 2)) t.push_back(p);
    for (const auto& p : poses(1500, 10)) t.push_back(p);
    return t;
  }();
  for (std::size_t i = 0; i < all.size(); ++i) expectSame(all[i], expected[i]);
  spill.remove();
  EXPECT_FALSE(std::filesystem::exists(path));
  EXPECT_EQ(spill.size(), 0);
  std::filesystem::remove_all(dir);
}

TEST(TrajectorySpill, AFullDiskNamesTheFileAndLosesNothing) {
  TrajectorySpill spill("/dev/full");
  try {
    spill.append(poses(0, 2000));
    FAIL() << "writing to /dev/full succeeded";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/dev/full"), std::string::npos) << e.what();
  }
  EXPECT_EQ(spill.size(), 0);
  EXPECT_THROW(spill.append(poses(2000, 10)), Error);
  const Trajectory kept = spill.read();  // still held in memory, in order
  ASSERT_EQ(kept.size(), 2010u);
  expectSame(kept[0], poses(0, 1)[0]);
  expectSame(kept[2009], poses(2009, 1)[0]);
}

}  // namespace
}  // namespace ldsm::drivers
