// The viewer of `ldsm run --serve`: a LiveSource over the running System and the server that
// publishes it, made only when --serve is given (without it nothing of the viewer is in the
// process: no thread, no socket, no snapshot).
#pragma once

#include <memory>
#include <string>

#include "ldsm/events.h"
#include "ldsm/system.h"
#include "listener_fanout.h"
#include "live_source.h"
#include "viewer_server.h"

namespace ldsm::viewer {

class RunViewer {
 public:
  /// `serve`: "[ADDR:]PORT"; `web_root`: empty for the default (findWebRoot()). Throws
  /// ldsm::ConfigError / InputError when the address is bad or cannot be bound, or the page is
  /// missing.
  RunViewer(System& system, const std::string& serve, const std::string& web_root,
            const std::string& source, const std::string& mode);

  /// The listener to give the System: `inner`'s events and the viewer's.
  SystemListener* listener(SystemListener* inner);
  /// The run is over: pages get the final state and are told so.
  void finish();
  std::string url() const { return server_->url(); }
  ViewerCounters counters() const { return server_->counters(); }

 private:
  LiveSource source_;
  std::unique_ptr<ViewerServer> server_;
  std::unique_ptr<ListenerFanout> fanout_;
};

}  // namespace ldsm::viewer
