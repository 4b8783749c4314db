// ldsm: one executable, thin subcommands (one file each, see commands.h).
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <opencv2/core/utility.hpp>
#include <string>

#include "commands.h"
#include "ldsm/drivers/allocator_policy.h"
#include "ldsm/error.h"
#include "logging.h"

int main(int argc, char** argv) {
  // Diagnostics (docs/determinism.md): LDSM_CV_UNOPTIMIZED=1 turns OpenCV's run-time dispatched
  // code paths off, a stand-in for a machine with fewer CPU features.
  if (const char* v = std::getenv("LDSM_CV_UNOPTIMIZED"); v != nullptr && std::string(v) == "1")
    cv::setUseOptimized(false);
  // Freed image-sized buffers go back to the system (ldsm/drivers/allocator_policy.h).
  ldsm::drivers::setHeapPolicy();
  CLI::App app{"ldsm: live monocular direct SLAM for robots", "ldsm"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("ldsm ") + LDSM_VERSION_STRING);
  std::string log_level = "warn";
  app.add_option("--log-level", log_level, "trace, debug, info, warn, error, off")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "off"}))
      ->capture_default_str();
  app.parse_complete_callback([&]() { ldsm::app::setupLogging(log_level); });

  ldsm::app::CommandResult result;
  ldsm::app::addConfigCommand(app, result);
  ldsm::app::addInfoCommand(app, result);
  ldsm::app::addSimCommand(app, result);
  ldsm::app::addEvalCommand(app, result);
  ldsm::app::addRunCommand(app, result);
  ldsm::app::addRecordCommand(app, result);
  ldsm::app::addCalibCommand(app, result);
  ldsm::app::addVocabCommand(app, result);
  ldsm::app::addViewCommand(app, result);
  ldsm::app::addMapCommand(app, result);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const ldsm::Error& e) {
    std::fprintf(stderr, "ldsm: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ldsm: unexpected error: %s\n", e.what());
    return 2;
  }
  return result.exit_code;
}
