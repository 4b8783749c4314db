#include "run_viewer.h"

namespace ldsm::viewer {

RunViewer::RunViewer(System& system, const std::string& serve, const std::string& web_root,
                     const std::string& source, const std::string& mode)
    : source_(system, source, mode) {
  system.publishTrackedImages();
  ViewerOptions options;
  parseServeAddress(serve, options);
  options.web_root = web_root;
  server_ = std::make_unique<ViewerServer>(source_, options);
}

SystemListener* RunViewer::listener(SystemListener* inner) {
  fanout_ = std::make_unique<ListenerFanout>(inner, &source_);
  return fanout_.get();
}

void RunViewer::finish() {
  source_.markFinished();
  server_->publishNow();
}

}  // namespace ldsm::viewer
