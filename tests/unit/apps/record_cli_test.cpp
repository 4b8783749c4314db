// `ldsm record` error paths that need no camera: a missing device, a node that is not a V4L2
// device, a bad pixel format, a missing --out. (Recording itself is tested on the fake device in
// record_test.cpp; the tool builds the same V4l2Source on the real kernel.)
#include <gtest/gtest.h>

#include <string>

#include "test_paths.h"

namespace ldsm {
namespace {

#if defined(LDSM_EXE)

struct CommandRun {
  int code = 0;
  std::string output;
};

CommandRun record(const std::string& args) {
  CommandRun r;
  r.code = test::runCommand(std::string(LDSM_EXE) + " record " + args, &r.output);
  return r;
}

void expectError(const CommandRun& r, const std::string& part) {
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("ldsm: error: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(part), std::string::npos) << "'" << part << "' not in: " << r.output;
}

TEST(RecordCli, MissingDeviceSaysWhatToDo) {
  const std::string dir = test::scratchDir("record_cli_missing");
  const CommandRun r = record("--device /dev/ldsm-no-such-video --out " + dir + "/rec --frames 3");
  expectError(r, "/dev/ldsm-no-such-video: cannot open");
  expectError(r, "device missing");
  expectError(r, "vivid");
  expectError(record("--device /dev/ldsm-no-such-video --list-formats"), "device missing");
}

TEST(RecordCli, NotAVideoDevice) {
  expectError(record("--device /dev/null --out " + test::scratchDir("record_cli_null")),
              "/dev/null: VIDIOC_QUERYCAP");
}

TEST(RecordCli, BadArguments) {
  expectError(record("--device /dev/null --out x --format RGB3"),
              "pixel format 'RGB3' is not one of GREY, Y10, Y16, YUYV, MJPEG");
  expectError(record("--device /dev/null"), "--out is required");
  const CommandRun negative = record("--device /dev/null --out x --frames -2");
  EXPECT_NE(negative.code, 0) << negative.output;
}

#endif

}  // namespace
}  // namespace ldsm
