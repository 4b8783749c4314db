#include "ldsm/drivers/trajectory_io.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "ldsm/error.h"
#include "synthetic_trajectory.h"

namespace ldsm::drivers {
namespace {

class TrajectoryIo : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = eval::testing::scratchDir("trajectory_io"); }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& text) {
    const std::string path = dir_ + "/" + name;
    std::ofstream(path) << text;
    return path;
  }

  // Reading `text` must fail with an InputError starting "<file>:<line>:" and naming `what`.
  void expectError(const std::string& text, int line, const std::string& what,
                   TrajectoryFormat format = TrajectoryFormat::Auto) {
    const std::string path = write("bad.txt", text);
    try {
      readTrajectory(path, format);
      FAIL() << "accepted:\n" << text;
    } catch (const InputError& e) {
      const std::string msg = e.what();
      const std::string prefix = line > 0 ? path + ":" + std::to_string(line) + ":" : path + ":";
      EXPECT_EQ(msg.rfind(prefix, 0), 0u) << msg;
      EXPECT_NE(msg.find(what), std::string::npos) << msg;
    }
  }

  std::string dir_;
};

void expectSameTrajectory(const Trajectory& a, const Trajectory& b, double tol) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_NEAR(a[i].timestamp, b[i].timestamp, tol);
    EXPECT_LE((a[i].pose.translation - b[i].pose.translation).norm(), tol);
    EXPECT_LT(a[i].pose.rotation.angularDistance(b[i].pose.rotation), 1e-7);
    EXPECT_LT(
        (a[i].pose.rotation.toRotationMatrix() - b[i].pose.rotation.toRotationMatrix()).norm(),
        1e-12);
  }
}

TEST_F(TrajectoryIo, TumRoundTripIsExact) {
  Trajectory t = eval::testing::curvedTrajectory(50, 0.0333333333, 1403715273.262142976);
  const std::string path = dir_ + "/traj.txt";
  writeTumTrajectory(path, t);
  EXPECT_EQ(detectTrajectoryFormat(path), TrajectoryFormat::Tum);
  const Trajectory back = readTrajectory(path);
  ASSERT_EQ(back.size(), t.size());
  for (std::size_t i = 0; i < t.size(); ++i) {
    EXPECT_EQ(back[i].timestamp, t[i].timestamp);  // shortest round-trip text: bit-exact
    EXPECT_EQ(back[i].pose.translation, t[i].pose.translation);
  }
  expectSameTrajectory(t, back, 0.0);
  // Only our files in the folder: the temporary file was renamed away.
  std::size_t files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir_)) {
    (void)entry;
    ++files;
  }
  EXPECT_EQ(files, 1u);
}

TEST_F(TrajectoryIo, KittiRoundTripWithAndWithoutTimes) {
  const Trajectory t = eval::testing::curvedTrajectory(40, 0.1);
  const std::string path = dir_ + "/poses.txt";
  writeKittiPoses(path, t);
  EXPECT_EQ(detectTrajectoryFormat(path), TrajectoryFormat::Kitti);
  std::vector<double> times;
  for (const auto& sp : t) times.push_back(sp.timestamp);
  expectSameTrajectory(t, readTrajectory(path, TrajectoryFormat::Auto, &times), 1e-12);

  const Trajectory indexed = readTrajectory(path, TrajectoryFormat::Kitti);
  ASSERT_EQ(indexed.size(), t.size());
  EXPECT_EQ(indexed[0].timestamp, 0.0);
  EXPECT_EQ(indexed[39].timestamp, 39.0);

  times.pop_back();
  try {
    readTrajectory(path, TrajectoryFormat::Kitti, &times);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("40 poses but 39 timestamps"), std::string::npos);
  }
}

TEST_F(TrajectoryIo, KittiRowMajorLayout) {
  // 90 deg about z: R = [0 -1 0; 1 0 0; 0 0 1], t = (1, 2, 3).
  const std::string path = write("k.txt", "0 -1 0 1  1 0 0 2  0 0 1 3\n");
  const Trajectory t = readTrajectory(path);
  ASSERT_EQ(t.size(), 1u);
  EXPECT_EQ(t[0].pose.translation, Eigen::Vector3d(1, 2, 3));
  const Eigen::Vector3d x_axis = t[0].pose.rotation * Eigen::Vector3d::UnitX();
  EXPECT_LT((x_axis - Eigen::Vector3d::UnitY()).norm(), 1e-12);
}

TEST_F(TrajectoryIo, EurocColumnOrder) {
  // Quaternion columns are w, x, y, z; timestamps are nanoseconds.
  const std::string text =
      "#timestamp [ns], p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], "
      "q_RS_z []\n"
      "1403715273262142976, 0.5, -1.25, 2.0, 0.5, 0.5, 0.5, 0.5\r\n"
      "1403715273312143104,0.6,-1.2,2.1,0.8,0,0,0.6\n";
  const std::string path = write("data.csv", text);
  EXPECT_EQ(detectTrajectoryFormat(path), TrajectoryFormat::EurocCsv);
  const Trajectory t = readTrajectory(path);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_NEAR(t[0].timestamp, 1403715273.262142976, 1e-6);
  EXPECT_NEAR(t[1].timestamp - t[0].timestamp, 0.050000128, 1e-6);
  EXPECT_EQ(t[0].pose.translation, Eigen::Vector3d(0.5, -1.25, 2.0));
  EXPECT_DOUBLE_EQ(t[1].pose.rotation.w(), 0.8);
  EXPECT_DOUBLE_EQ(t[1].pose.rotation.z(), 0.6);
  EXPECT_DOUBLE_EQ(t[1].pose.rotation.x(), 0.0);

  // The 17-column state estimate (velocity and biases) and a header without '#'.
  const std::string state =
      "timestamp,px,py,pz,qw,qx,qy,qz,vx,vy,vz,bwx,bwy,bwz,bax,bay,baz\n"
      "1000000000,1,2,3,1,0,0,0,0,0,0,0,0,0,0,0,0\n";
  const Trajectory s = readTrajectory(write("state.csv", state), TrajectoryFormat::EurocCsv);
  ASSERT_EQ(s.size(), 1u);
  EXPECT_DOUBLE_EQ(s[0].timestamp, 1.0);
}

TEST_F(TrajectoryIo, CommentsBlankLinesAndNearUnitQuaternions) {
  const std::string path = write("t.txt",
                                 "# header\n\n"
                                 "0.0 1 2 3 0 0 0 1.0005\n"
                                 "  # indented comment\n"
                                 "0.1\t1 2 3 0 0 0 1\n");
  const Trajectory t = readTrajectory(path);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_NEAR(t[0].pose.rotation.norm(), 1.0, 1e-15);
}

TEST_F(TrajectoryIo, BadInputNamesFileAndLine) {
  expectError("0 1 2 3 0 0 0 1\n1 1 2 3 0 0 1\n", 2, "expected 8 columns", TrajectoryFormat::Tum);
  expectError("# c\n0 1 2 3 0 0 0 1\n1 1 abc 3 0 0 0 1\n", 3, "'abc') is not a number");
  expectError("0 1 2 3 0 0 0 1\n1 1 nan 3 0 0 0 1\n", 2, "is not finite");
  expectError("0 1 2 3 0 0 0 1\n1 1 2 3 0 0 0 1.1\n", 2, "has norm");
  expectError("0 1 2 3 0 0 0 1\n0 1 2 3 0 0 0 1\n", 2, "is not greater than the previous");
  expectError("5 1 2 3 0 0 0 1\n\n4 1 2 3 0 0 0 1\n", 3, "(5 at line 1)");
  expectError("0 1 2 3 0\n", 1, "cannot detect the trajectory format");
  expectError("1 0 0 0 0 1 0 0 0 0 2 0\n", 1, "not a rotation matrix");
  expectError("1 0 0 0 0 1 0 0 0 0 1\n", 1, "expected 12 columns", TrajectoryFormat::Kitti);
  expectError("#t,x,y,z,w,x,y,z\n1,0,0,0,1,0,0\n", 2, "expected 8 or 17 comma-separated");
  expectError("#t,x,y,z,w,x,y,z\n1,0,0,0,1,0,0,0\n2,0,0,,1,0,0,0\n", 3, "column 4 ('')");
  expectError("", 0, "no poses");
  expectError("# only a comment\n\n", 0, "no poses");
}

TEST_F(TrajectoryIo, MissingFileAndDirectory) {
  EXPECT_THROW(readTrajectory(dir_ + "/missing.txt"), InputError);
  try {
    readTrajectory(dir_);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("is a directory"), std::string::npos);
  }
}

TEST_F(TrajectoryIo, TimestampLists) {
  const auto one = readTimestampList(write("times.txt", "0.0\n1.037359e-01\n0.2073381\n"));
  ASSERT_EQ(one.size(), 3u);
  EXPECT_DOUBLE_EQ(one[1], 0.1037359);
  const auto two = readTimestampList(write("times2.txt", "00000 0.5 20.0\n00001 0.6 20.0\n"));
  ASSERT_EQ(two.size(), 2u);
  EXPECT_DOUBLE_EQ(two[1], 0.6);
  EXPECT_THROW(readTimestampList(write("times3.txt", "1\n1\n")), InputError);
  EXPECT_THROW(readTimestampList(write("times4.txt", "1\nx\n")), InputError);
}

TEST_F(TrajectoryIo, FormatNames) {
  EXPECT_EQ(parseTrajectoryFormat("euroc"), TrajectoryFormat::EurocCsv);
  EXPECT_STREQ(trajectoryFormatName(TrajectoryFormat::Kitti), "kitti");
  EXPECT_THROW(parseTrajectoryFormat("csv"), ConfigError);
}

TEST_F(TrajectoryIo, WritingToAMissingFolderFails) {
  const Trajectory t = eval::testing::curvedTrajectory(3);
  try {
    writeTumTrajectory(dir_ + "/no/such/dir/t.txt", t);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no/such/dir/t.txt: cannot write"), std::string::npos)
        << e.what();
  }
}

TEST_F(TrajectoryIo, ReadsSharedGroundTruthInEveryFormat) {
  const std::string data = LDSM_SHARED_DATA;
  if (!std::filesystem::exists(data + "/kitti00_200/poses/00.txt")) {
    GTEST_SKIP() << "../shared/data absent: skipping the real KITTI files";
  }
  const auto times = readTimestampList(data + "/kitti00_200/sequences/00/times.txt");
  const Trajectory kitti =
      readTrajectory(data + "/kitti00_200/poses/00.txt", TrajectoryFormat::Auto, &times);
  const Trajectory tum = readTrajectory(data + "/kitti00_200/groundtruth.txt");
  ASSERT_EQ(kitti.size(), 200u);
  ASSERT_EQ(tum.size(), 200u);
  for (std::size_t i = 0; i < 200; ++i) {
    EXPECT_NEAR(kitti[i].timestamp, tum[i].timestamp, 1e-5);
    EXPECT_LT((kitti[i].pose.translation - tum[i].pose.translation).norm(), 1e-5);
    EXPECT_LT(kitti[i].pose.rotation.angularDistance(tum[i].pose.rotation), 1e-5);
  }
}

}  // namespace
}  // namespace ldsm::drivers
