// `ldsm view DIR`: serves the outputs of a finished run (trajectory.txt, keyframes.txt,
// points.ply, stats.json) in the browser viewer, the same page as `ldsm run --serve`, until
// Ctrl-C.
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <thread>

#include "commands.h"
#include "interrupt.h"
#include "viewer/run_folder_source.h"
#include "viewer/viewer_server.h"

namespace ldsm::app {
namespace {

struct ViewOptions {
  std::string dir;
  std::string serve = "8080";
  std::string web_root;
  double seconds = 0.0;  ///< stop after this long (0: at Ctrl-C)
};

int view(const ViewOptions& o) {
  viewer::RunFolderSource source(o.dir);
  viewer::ViewerOptions options;
  viewer::parseServeAddress(o.serve, options);
  options.web_root = o.web_root;
  const InterruptHandler interrupt;
  viewer::ViewerServer server(source, options);
  std::fprintf(stderr, "viewer: %s serves %s; Ctrl-C stops\n", server.url().c_str(), o.dir.c_str());
  const auto start = std::chrono::steady_clock::now();
  while (!InterruptHandler::requested()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    if (o.seconds > 0.0 &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >=
            o.seconds)
      break;
  }
  return 0;
}

}  // namespace

void addViewCommand(CLI::App& app, CommandResult& result) {
  auto* cmd = app.add_subcommand("view", "Show the outputs of a finished run in the browser");
  auto o = std::make_shared<ViewOptions>();
  cmd->add_option("dir", o->dir, "Output folder of `ldsm run`")->required();
  cmd->add_option("--serve", o->serve, "[ADDR:]PORT to serve at (default address 127.0.0.1)")
      ->capture_default_str();
  cmd->add_option("--web-root", o->web_root,
                  "The viewer's page folder (default: share/ldsm/web beside the executable)");
  cmd->add_option("--seconds", o->seconds, "Stop after this many seconds (0: at Ctrl-C)")
      ->check(CLI::Range(0.0, 1e9))
      ->capture_default_str();
  cmd->callback([o, &result]() { result.exit_code = view(*o); });
}

}  // namespace ldsm::app
