// `ldsm view`'s source: a run's output folder read into one snapshot; missing files are left out,
// malformed ones are errors naming the file.
#include <gtest/gtest.h>

#include <fstream>

#include "ldsm/drivers/ply_writer.h"
#include "ldsm/error.h"
#include "run_folder_source.h"
#include "test_paths.h"

namespace ldsm::viewer {
namespace {

TEST(RunFolderSource, ReadsTheRunOutputs) {
  const std::string dir = test::scratchDir("run_folder_source");
  std::ofstream(dir + "/trajectory.txt")
      << "# t tx ty tz qx qy qz qw\n0.0 0 0 0 0 0 0 1\n0.1 1 2 3 0 0 0 1\n";
  std::ofstream(dir + "/keyframes.txt") << "# header only: no keyframes yet\n";
  drivers::writePly(dir + "/points.ply", {{1.f, 2.f, 3.f}, {4.f, 5.f, 6.f}},
                    {{{100, 100, 100}}, {{255, 64, 0}}});
  std::ofstream(dir + "/stats.json")
      << R"({"tracking_status": "tracking", "frames": 12, "keyframes": 3,
             "pipeline": {"dropped_frames": 2, "latency": {"submit_to_tracked":
             {"mean_ms": 4.5, "p99_ms": 9.5}}}, "loops": [{"keyframe": 7, "matched_keyframe": 1}]})";
  RunFolderSource source(dir);
  const ViewerSnapshot s = source.snapshot(true);
  ASSERT_EQ(s.trajectory.size(), 2u * kPoseStride);
  EXPECT_EQ(s.trajectory[kPoseStride + 2], 3.f);
  EXPECT_TRUE(s.has_current);
  EXPECT_EQ(s.current[0], 1.f);
  EXPECT_TRUE(s.keyframes.empty());
  ASSERT_EQ(s.points.size(), 2u * kPointStride);
  EXPECT_EQ(s.points[3], 100.f);  // grey: the intensity
  EXPECT_EQ(s.points[7], -1.f);   // coloured: a corner
  EXPECT_EQ(s.figures.frames, 12);
  EXPECT_EQ(s.figures.dropped_frames, 2);
  EXPECT_DOUBLE_EQ(s.figures.latency_p99_ms, 9.5);
  EXPECT_EQ(s.figures.loops, 1);
  EXPECT_TRUE(s.loops.empty());  // its keyframes are not in keyframes.txt
  EXPECT_TRUE(s.figures.finished);
}

TEST(RunFolderSource, EmptyOrBrokenFoldersAreErrors) {
  const std::string dir = test::scratchDir("run_folder_source_bad");
  EXPECT_THROW(RunFolderSource{dir}, InputError);  // none of the files
  EXPECT_THROW(RunFolderSource{dir + "/missing"}, InputError);
  std::ofstream(dir + "/stats.json") << "{ not json";
  try {
    RunFolderSource source(dir);
    ADD_FAILURE() << "no error for a malformed stats.json";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("stats.json"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ldsm::viewer
