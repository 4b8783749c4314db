#include "viewer_server.h"

#include <civetweb.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <mutex>
#include <utility>
#include <vector>

#include "ldsm/error.h"
#include "web_files.h"

namespace ldsm::viewer {
namespace {

// civetweb's library initialisation is process-wide: counted here.
std::mutex g_library_mutex;
int g_library_users = 0;

void acquireLibrary() {
  std::lock_guard<std::mutex> lock(g_library_mutex);
  if (g_library_users++ == 0) mg_init_library(MG_FEATURES_WEBSOCKET);
}

void releaseLibrary() {
  std::lock_guard<std::mutex> lock(g_library_mutex);
  if (--g_library_users == 0) mg_exit_library();
}

}  // namespace

void parseServeAddress(const std::string& text, ViewerOptions& o) {
  auto bad = [&](const std::string& why) {
    return ConfigError("--serve " + text + ": " + why + " (expected [ADDR:]PORT, e.g. 8080 or " +
                       "0.0.0.0:8080)");
  };
  std::string address = o.address, port = text;
  const auto colon = text.rfind(':');
  if (colon != std::string::npos) {
    address = text.substr(0, colon);
    port = text.substr(colon + 1);
    if (address.size() >= 2 && address.front() == '[' && address.back() == ']') {
      if (address.size() == 2) throw bad("empty address");
    } else if (address.empty() || address.find_first_of("[]:/ ") != std::string::npos) {
      throw bad("bad address");
    }
  }
  if (port.empty() || port.size() > 5 || port.find_first_not_of("0123456789") != std::string::npos)
    throw bad("bad port");
  const long p = std::strtol(port.c_str(), nullptr, 10);
  if (p > 65535) throw bad("port out of range");
  o.address = address;
  o.port = static_cast<int>(p);
}

struct ViewerServer::Impl {
  Impl(SnapshotSource& source, const ViewerOptions& o)
      : options(o), files(findWebRoot(o.web_root)), publisher(source, o.publisher) {}

  /// A complete response. (Not mg_send_http_error: Debian's civetweb 1.15 crashed in it on a
  /// browser's favicon request.)
  static int respond(mg_connection* conn, int status, const char* reason, const char* type,
                     const std::string& body, bool with_body) {
    mg_printf(conn,
              "HTTP/1.1 %d %s\r\nContent-Type: %s\r\nContent-Length: %zu\r\n"
              "Cache-Control: no-cache\r\nX-Content-Type-Options: nosniff\r\n"
              "Connection: close\r\n\r\n",
              status, reason, type, body.size());
    if (with_body) mg_write(conn, body.data(), body.size());
    return status;
  }

  static int onHttp(mg_connection* conn, void* data) {
    auto* self = static_cast<Impl*>(data);
    const mg_request_info* ri = mg_get_request_info(conn);
    const std::string method = ri->request_method ? ri->request_method : "";
    if (method != "GET" && method != "HEAD")
      return respond(conn, 405, "Method Not Allowed", "text/plain", "only GET and HEAD\n", true);
    const std::string path = ri->local_uri_raw ? ri->local_uri_raw : "";
    const WebFile* f = self->files.find(path);
    if (f == nullptr) return respond(conn, 404, "Not Found", "text/plain", "not found\n", true);
    return respond(conn, 200, "OK", f->content_type.c_str(), f->body, method == "GET");
  }

  static int onWsConnect(const mg_connection*, void* data) {
    auto* self = static_cast<Impl*>(data);
    // Admitted here, counted until its close handler runs.
    int now = self->admitted.load();
    do {
      if (now >= self->options.max_clients) {
        self->refused.fetch_add(1);
        spdlog::info("viewer: page refused ({} connected, the limit)", now);
        return 1;
      }
    } while (!self->admitted.compare_exchange_weak(now, now + 1));
    return 0;
  }

  static void onWsReady(mg_connection* conn, void* data) {
    auto* self = static_cast<Impl*>(data);
    auto channel = std::make_shared<ClientChannel>([conn](const WireMessage& m) {
      const int op = m.binary ? MG_WEBSOCKET_OPCODE_BINARY : MG_WEBSOCKET_OPCODE_TEXT;
      // mg_websocket_write locks the connection itself (civetweb's read loop writes too).
      return mg_websocket_write(conn, op, m.bytes.data(), m.bytes.size()) > 0;
    });
    mg_set_user_connection_data(conn, channel.get());
    {
      std::lock_guard<std::mutex> lock(self->channels_mutex);
      self->channels.emplace_back(conn, channel);
    }
    self->accepted.fetch_add(1);
    self->publisher.add(channel);
    spdlog::info("viewer: page connected from {}", mg_get_request_info(conn)->remote_addr);
  }

  static int onWsData(mg_connection* conn, int bits, char*, std::size_t len, void* data) {
    auto* self = static_cast<Impl*>(data);
    const int opcode = bits & 0x0f;
    if (opcode == MG_WEBSOCKET_OPCODE_CONNECTION_CLOSE) return 0;
    if (len > self->options.max_incoming_bytes) {
      self->closed_for_input.fetch_add(1);
      spdlog::info("viewer: page sent a {}-byte message, closing it", len);
      (void)conn;
      return 0;
    }
    return 1;  // the page only sends keep-alives: anything else is ignored
  }

  static void onWsClose(const mg_connection* conn, void* data) {
    auto* self = static_cast<Impl*>(data);
    auto* channel = static_cast<ClientChannel*>(mg_get_user_connection_data(conn));
    if (channel != nullptr) {
      self->publisher.remove(channel);
      std::shared_ptr<ClientChannel> owned;
      {
        std::lock_guard<std::mutex> lock(self->channels_mutex);
        for (auto it = self->channels.begin(); it != self->channels.end(); ++it)
          if (it->second.get() == channel) {
            owned = it->second;
            self->channels.erase(it);
            break;
          }
      }
      if (owned) owned->stop();  // no more writes to this connection after this returns
    }
    self->admitted.fetch_sub(1);
    spdlog::info("viewer: page disconnected");
  }

  ViewerOptions options;
  WebFiles files;
  Publisher publisher;
  mg_context* ctx = nullptr;
  int bound_port = 0;
  std::mutex channels_mutex;
  std::vector<std::pair<mg_connection*, std::shared_ptr<ClientChannel>>> channels;
  std::atomic<int> admitted{0};
  std::atomic<std::int64_t> accepted{0}, refused{0}, closed_for_input{0};
};

ViewerServer::ViewerServer(SnapshotSource& source, const ViewerOptions& options) {
  impl_ = std::make_unique<Impl>(source, options);
  acquireLibrary();
  const std::string ports = options.address + ":" + std::to_string(options.port);
  // One thread per open page plus two for page loads.
  const std::string threads = std::to_string(std::max(options.max_clients, 1) + 2);
  const char* config[] = {"listening_ports",
                          ports.c_str(),
                          "num_threads",
                          threads.c_str(),
                          "request_timeout_ms",
                          "10000",
                          "websocket_timeout_ms",
                          "3600000",
                          "max_request_size",
                          "16384",
                          "enable_keep_alive",
                          "no",
                          nullptr};
  mg_callbacks callbacks{};
  callbacks.log_message = [](const mg_connection*, const char* message) {
    spdlog::debug("viewer (civetweb): {}", message);
    return 1;
  };
  impl_->ctx = mg_start(&callbacks, nullptr, config);
  if (impl_->ctx == nullptr) {
    impl_->publisher.stop();
    releaseLibrary();
    throw ConfigError("--serve: cannot listen on " + ports +
                      " (address not on this machine, or port in use)");
  }
  mg_set_request_handler(impl_->ctx, "/", &Impl::onHttp, impl_.get());
  mg_set_websocket_handler(impl_->ctx, "/ws", &Impl::onWsConnect, &Impl::onWsReady, &Impl::onWsData,
                           &Impl::onWsClose, impl_.get());
  mg_server_port bound[4]{};
  const int n = mg_get_server_ports(impl_->ctx, 4, bound);
  impl_->bound_port = n > 0 ? bound[0].port : options.port;
  spdlog::info("viewer: serving {} ({} files from {})", url(), impl_->files.size(),
               impl_->files.root());
}

ViewerServer::~ViewerServer() {
  impl_->publisher.stop();
  {
    // Pages are told to close (civetweb would otherwise wait up to 10 s for their next read to
    // time out); held under the lock, no connection can go away meanwhile.
    std::lock_guard<std::mutex> lock(impl_->channels_mutex);
    for (const auto& entry : impl_->channels)
      mg_websocket_write(entry.first, MG_WEBSOCKET_OPCODE_CONNECTION_CLOSE, "", 0);
  }
  mg_stop(impl_->ctx);  // closes every page (their close handlers stop their channels)
  releaseLibrary();
}

int ViewerServer::port() const {
  return impl_->bound_port;
}

std::string ViewerServer::url() const {
  const std::string host =
      impl_->options.address == "0.0.0.0" ? std::string("127.0.0.1") : impl_->options.address;
  return "http://" + host + ":" + std::to_string(port()) + "/";
}

void ViewerServer::publishNow() {
  impl_->publisher.publishNow();
}

ViewerCounters ViewerServer::counters() const {
  ViewerCounters c;
  c.pages_connected = impl_->admitted.load();
  c.pages_accepted = impl_->accepted.load();
  c.pages_refused = impl_->refused.load();
  c.pages_closed_for_input = impl_->closed_for_input.load();
  c.publisher = impl_->publisher.counters();
  return c;
}

}  // namespace ldsm::viewer
