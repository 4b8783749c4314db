// `ldsm run` when things go wrong around it (docs/reliability.md): a disk that fills up, SIGTERM
// from a supervisor, a process killed outright mid-run, a second Ctrl-C. Nothing already computed
// may be lost or left truncated, and every error names the file.
#include <gtest/gtest.h>

#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "interrupt.h"
#include "ldsm/drivers/sim/sim_source.h"
#include "ldsm/drivers/sim/tum_mono_writer.h"
#include "test_paths.h"

namespace ldsm {
namespace {

/// Poses in a TUM trajectory file; -1 when a line is not a whole pose (8 numbers).
int wholePoses(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  int poses = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ss(line);
    double v;
    int fields = 0;
    while (ss >> v) ++fields;
    if (fields != 8 || !ss.eof()) return -1;
    ++poses;
  }
  return poses;
}

std::vector<std::string> leftovers(const std::string& dir) {
  std::vector<std::string> tmp;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().filename().string().find(".tmp.") != std::string::npos)
      tmp.push_back(e.path().string());
  return tmp;
}

#if defined(LDSM_EXE)

/// A 60-frame synthetic corridor at 320x240 (2 s at 30 fps) in TUM-Mono layout.
class RunFaults : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = test::scratchDir("run_faults_" + std::to_string(::getpid()));
    drivers::sim::SimOptions o;
    o.width = 320;
    o.height = 240;
    o.frames = 60;
    drivers::sim::SimSource source("forward", o);
    drivers::sim::writeTumMonoSequence(source, dir_ + "/seq");
  }
  static void TearDownTestSuite() { std::filesystem::remove_all(dir_); }

  static std::string ldsmRun(const std::string& args) {
    return std::string(LDSM_EXE) + " run --dataset " + dir_ + "/seq " + args;
  }
  /// Starts `command` in the background from a shell script, waits (up to 60 s) until `ready` is
  /// true of the folder, sends `signal` and reports the command's exit status; the output of
  /// the command goes to `log`.
  static int signalWhen(const std::string& command, const std::string& ready_test,
                        const std::string& signals, const std::string& log, std::string* out) {
    const std::string script = command + " > " + log + " 2>&1 & pid=$!\n" + "i=0; until " +
                               ready_test +
                               "; do i=$((i+1)); [ $i -gt 600 ] && break; sleep 0.1; done\n" +
                               signals + "\nwait $pid; echo \"status=$?\"";
    std::string output;
    test::runCommand("sh -c '" + script + "'", &output);
    *out = output + test::readFile(log);
    const auto at = output.find("status=");
    return at == std::string::npos ? -1 : std::stoi(output.substr(at + 7));
  }
  static std::string dir_;
};

std::string RunFaults::dir_;

TEST_F(RunFaults, AFullDiskKeepsTheEarlierOutputsWholeAndNamesEveryFile) {
  const std::string out = dir_ + "/full";
  std::string log;
  ASSERT_EQ(test::runCommand(ldsmRun("--deterministic --out " + out), &log), 0) << log;
  const std::vector<std::string> files = {"trajectory.txt", "keyframes.txt", "points.ply",
                                          "stats.json"};
  std::vector<std::string> before;
  for (const std::string& f : files) before.push_back(test::readFile(out + "/" + f));
  ASSERT_GT(wholePoses(out + "/trajectory.txt"), 30);

  // The same run again into the same folder, where no file may grow past 1 KiB (RLIMIT_FSIZE;
  // with SIGXFSZ ignored, write() fails with EFBIG as it fails with ENOSPC on a full disk).
  const int rc = test::runCommand(
      "sh -c \"trap '' XFSZ; ulimit -f 2; exec " + ldsmRun("--deterministic --out " + out) + "\"",
      &log);
  EXPECT_EQ(rc, 1) << log;
  for (const std::string& f : files) {
    EXPECT_NE(log.find(out + "/" + f + ": cannot write"), std::string::npos) << f << "\n" << log;
  }
  EXPECT_NE(log.find("File too large"), std::string::npos) << log;
  EXPECT_NE(log.find("incomplete"), std::string::npos) << log;
  // The run's own figures are still reported ...
  EXPECT_NE(log.find("finished: 60 frames"), std::string::npos) << log;
  // ... and the files of the first run are untouched, with no temporary file left behind.
  for (std::size_t i = 0; i < files.size(); ++i)
    EXPECT_EQ(test::readFile(out + "/" + files[i]), before[i]) << files[i];
  EXPECT_TRUE(leftovers(out).empty());
}

TEST_F(RunFaults, SigtermStopsLikeCtrlCAndKeepsTheResults) {
  const std::string out = dir_ + "/term";
  std::string log;
  // Replayed at a quarter of its speed (8 s), so that a slow machine keeps every frame.
  // Signalled once it tracks (a pose in the periodically flushed trajectory).
  const int rc = signalWhen(ldsmRun("--realtime --speed 0.25 --flush-every 0.2 --out " + out),
                            "grep -q ^[0-9] " + out + "/trajectory.txt 2>/dev/null",
                            "kill -TERM $pid", out + ".log", &log);
  EXPECT_EQ(rc, 1) << log;  // a recorded sequence that did not reach its end
  EXPECT_NE(log.find("stopping after this frame"), std::string::npos) << log;
  const std::string stats = test::readFile(out + "/stats.json");
  EXPECT_NE(stats.find("\"status\": \"stopped: interrupted\""), std::string::npos) << stats;
  EXPECT_GE(wholePoses(out + "/trajectory.txt"), 1) << log;
  EXPECT_TRUE(leftovers(out).empty());
}

TEST_F(RunFaults, AKilledRunLeavesTheTrajectoryOfItsLastFlushWhole) {
  const std::string out = dir_ + "/kill";
  std::string log;
  // Killed outright (no handler runs) once the first periodic flush has written the trajectory.
  const int rc = signalWhen(ldsmRun("--realtime --speed 0.25 --flush-every 0.2 --out " + out),
                            "grep -q ^[0-9] " + out + "/trajectory.txt 2>/dev/null",
                            "kill -KILL $pid", out + ".log", &log);
  EXPECT_EQ(rc, 128 + SIGKILL) << log;
  EXPECT_GE(wholePoses(out + "/trajectory.txt"), 1) << test::readFile(out + "/trajectory.txt");
  EXPECT_GE(wholePoses(out + "/keyframes.txt"), 0);
  EXPECT_FALSE(std::filesystem::exists(out + "/stats.json")) << "written only at the end";
}

TEST_F(RunFaults, FlushingCanBeTurnedOffAndRejectsNonsense) {
  std::string log;
  EXPECT_NE(test::runCommand(ldsmRun("--flush-every -1 --out " + dir_ + "/bad"), &log), 0);
  EXPECT_NE(log.find("--flush-every"), std::string::npos) << log;
  EXPECT_EQ(
      test::runCommand(ldsmRun("--deterministic --flush-every 0 --out " + dir_ + "/off"), &log), 0)
      << log;
}

#endif

// The handler itself, in a child process: the first signal only asks to stop; a second quits at
// once with status 130 however busy the process is.
TEST(InterruptHandler, FirstSignalAsksToStopSecondQuitsAtOnce) {
  EXPECT_EXIT(
      {
        const app::InterruptHandler handler;
        if (app::InterruptHandler::requested()) std::_Exit(3);
        std::raise(SIGTERM);
        if (!app::InterruptHandler::requested()) std::_Exit(4);
        std::raise(SIGINT);
        std::_Exit(5);  // not reached
      },
      ::testing::ExitedWithCode(130), "interrupted twice: quitting now");
}

TEST(InterruptHandler, RestoresThePreviousHandlers) {
  EXPECT_EXIT(
      {
        { const app::InterruptHandler handler; }
        std::raise(SIGTERM);  // the default action again
        std::_Exit(0);
      },
      ::testing::KilledBySignal(SIGTERM), "");
}

}  // namespace
}  // namespace ldsm
