// The browser viewer's server: an HTTP server (civetweb) serving the page's files (web_files.h)
// and, on GET /stream, the live updates of a Publisher as one chunked response per page
// (wire_format.h). Data only flows to the page: nothing a client sends after its request header
// is read, and civetweb's WebSocket support is never reached (every request is answered by ldsm
// before civetweb's own routing; request_policy.h). Safe by default: it binds 127.0.0.1 unless
// told otherwise, serves only its own files and accepts at most `max_clients` pages.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "publisher.h"
#include "snapshot.h"

namespace ldsm::viewer {

struct ViewerOptions {
  std::string address = "127.0.0.1";
  int port = 8080;       ///< 0: any free port (see ViewerServer::port())
  std::string web_root;  ///< empty: findWebRoot()
  int max_clients = 4;
  /// A request header not complete after this long, or a write to a page that makes no progress
  /// for this long (a page that stopped reading), closes that connection.
  int timeout_ms = 10000;
  PublisherOptions publisher;
};

/// Reads "[ADDR:]PORT" (e.g. "8080", "0.0.0.0:8080", "[::1]:8080") into `options`. Throws
/// ldsm::ConfigError naming the text when it is not that.
void parseServeAddress(const std::string& text, ViewerOptions& options);

struct ViewerCounters {
  std::int64_t pages_connected = 0;   ///< now
  std::int64_t pages_accepted = 0;    ///< since start
  std::int64_t pages_refused = 0;     ///< over max_clients
  std::int64_t requests_refused = 0;  ///< malformed, upgrades, bodies, methods other than GET/HEAD
  PublisherCounters publisher;
};

class ViewerServer {
 public:
  /// Starts serving; throws ldsm::ConfigError when the address cannot be bound and
  /// ldsm::InputError when the web folder is missing.
  ViewerServer(SnapshotSource& source, const ViewerOptions& options);
  ~ViewerServer();
  ViewerServer(const ViewerServer&) = delete;
  ViewerServer& operator=(const ViewerServer&) = delete;

  int port() const;
  /// e.g. "http://127.0.0.1:8080/"
  std::string url() const;
  /// Sends the current state to every page now (call before stopping at the end of a run).
  void publishNow();
  ViewerCounters counters() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace ldsm::viewer
