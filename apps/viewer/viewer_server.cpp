#include "viewer_server.h"

#include <civetweb.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <mutex>
#include <utility>
#include <vector>

#include "http_reply.h"
#include "ldsm/error.h"
#include "request_policy.h"
#include "thread_priority.h"
#include "thread_stack_floor.h"
#include "web_files.h"

namespace ldsm::viewer {
namespace {

/// civetweb's last message while the server starts (mg_start reports failures only there), of
/// the starting thread.
std::string& lastStartMessage() {
  thread_local std::string message;
  return message;
}

// civetweb's library initialisation is process-wide: counted here.
std::mutex g_library_mutex;
int g_library_users = 0;

void acquireLibrary() {
  std::lock_guard<std::mutex> lock(g_library_mutex);
  if (g_library_users++ == 0) mg_init_library(MG_FEATURES_DEFAULT);  // no TLS, no Lua
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

  static Impl* of(const mg_connection* conn) {
    return static_cast<Impl*>(mg_get_user_data(mg_get_context(conn)));
  }

  /// civetweb's begin_request: every request is answered here, so civetweb's own routing (files,
  /// scripts, WebSocket handshakes) never runs. A positive return is the status for civetweb's
  /// log; -1 makes civetweb 1.15 close the connection without reading further (it would
  /// otherwise read and discard the announced body).
  static int onRequest(mg_connection* conn) {
    Impl* self = of(conn);
    const mg_request_info* ri = mg_get_request_info(conn);
    RequestFacts facts;
    facts.method = ri->request_method ? ri->request_method : "";
    facts.path = ri->local_uri_raw ? ri->local_uri_raw : "";
    facts.upgrade = mg_get_header(conn, "Upgrade") != nullptr;
    facts.has_body = announcesBody(mg_get_header(conn, "Content-Length"),
                                   mg_get_header(conn, "Transfer-Encoding"));
    const RequestVerdict verdict = judgeRequest(facts);
    switch (verdict.route) {
      case Route::Stream:
        return self->stream(conn);
      case Route::File: {
        const WebFile* f = self->files.find(facts.path);
        if (f == nullptr) return writeResponse(conn, 404, "text/plain", "not found\n", true);
        return writeResponse(conn, 200, f->content_type.c_str(), f->body, facts.method == "GET");
      }
      case Route::Refuse:
        break;
    }
    self->refused_requests.fetch_add(1);
    writeResponse(conn, verdict.status, "text/plain", verdict.message, true);
    return verdict.read_nothing_more ? -1 : verdict.status;
  }

  /// civetweb's http_error: its own errors (a malformed, oversized or incomplete request header)
  /// are answered by ldsm too; the connection is closed afterwards.
  static int onHttpError(mg_connection* conn, int status, const char*) {
    of(conn)->refused_requests.fetch_add(1);
    writeResponse(conn, status, "text/plain", std::string(reasonPhrase(status)) + "\n", true);
    return 0;
  }

  /// GET /stream on the page's connection thread: admitted, it is sent the publisher's batches
  /// as chunks until the server stops or a write fails (the page went away, or stopped reading
  /// for request_timeout_ms).
  int stream(mg_connection* conn) {
    int now = admitted.load();
    do {
      if (now >= options.max_clients) {
        refused.fetch_add(1);
        spdlog::info("viewer: page refused ({} connected, the limit)", now);
        return writeResponse(conn, 503, "text/plain", "too many pages open\n", true);
      }
    } while (!admitted.compare_exchange_weak(now, now + 1));
    auto channel = std::make_shared<ClientChannel>();
    {
      std::lock_guard<std::mutex> lock(channels_mutex);
      if (stopping) {
        admitted.fetch_sub(1);
        return writeResponse(conn, 503, "text/plain", "the viewer is stopping\n", true);
      }
      channels.push_back(channel);
    }
    bool ended_by_server = false;
    if (writeStreamHead(conn)) {
      accepted.fetch_add(1);
      spdlog::info("viewer: page connected from {}", mg_get_request_info(conn)->remote_addr);
      publisher.add(channel);
      ended_by_server = channel->serve([conn](const WireMessage& m) {
        return mg_send_chunk(conn, m.bytes.data(), static_cast<unsigned>(m.bytes.size())) > 0;
      });
      publisher.remove(channel.get());
      spdlog::info("viewer: page disconnected");
    }
    if (ended_by_server) mg_send_chunk(conn, "", 0);  // the last chunk: a complete response
    {
      std::lock_guard<std::mutex> lock(channels_mutex);
      channels.erase(std::remove(channels.begin(), channels.end(), channel), channels.end());
    }
    channels_cv.notify_all();
    admitted.fetch_sub(1);
    return 200;
  }

  /// Admits no more pages and ends every stream after the batch it was offered last (the final
  /// state), waiting up to `limit` for them: a page that stopped reading is then cut off by
  /// mg_stop, which ends any write.
  void stopStreams(std::chrono::milliseconds limit) {
    std::unique_lock<std::mutex> lock(channels_mutex);
    stopping = true;
    for (const auto& c : channels) c->stop();
    channels_cv.wait_for(lock, limit, [this] { return channels.empty(); });
  }

  ViewerOptions options;
  WebFiles files;
  Publisher publisher;
  mg_context* ctx = nullptr;
  int bound_port = 0;
  std::mutex channels_mutex;
  std::condition_variable channels_cv;
  std::vector<std::shared_ptr<ClientChannel>> channels;
  bool stopping = false;
  std::atomic<int> admitted{0};
  std::atomic<std::int64_t> accepted{0}, refused{0}, refused_requests{0};
};

ViewerServer::ViewerServer(SnapshotSource& source, const ViewerOptions& options) {
  impl_ = std::make_unique<Impl>(source, options);
  acquireLibrary();
  const std::string ports = options.address + ":" + std::to_string(options.port);
  // One thread per open page plus two for page loads.
  const std::string threads = std::to_string(std::max(options.max_clients, 1) + 2);
  const std::string timeout = std::to_string(std::max(options.timeout_ms, 100));
  const char* config[] = {"listening_ports", ports.c_str(), "num_threads", threads.c_str(),
                          "request_timeout_ms", timeout.c_str(), "max_request_size", "16384",
                          "enable_keep_alive", "no",
                          // Paths are looked up as they were sent (web_files.h).
                          "decode_url", "no",
                          // Chunks go out at once (a chunk is three writes).
                          "tcp_nodelay", "1", nullptr};
  mg_callbacks callbacks{};
  callbacks.begin_request = &Impl::onRequest;
  callbacks.http_error = &Impl::onHttpError;
  callbacks.init_thread = [](const mg_context*, int) -> void* {
    lowerThisThreadPriority();  // civetweb's threads, the pages' senders among them
    return nullptr;
  };
  callbacks.log_message = [](const mg_connection*, const char* message) {
    spdlog::debug("viewer (civetweb): {}", message);
    lastStartMessage() = message;
    return 1;
  };
  if (!threadStackFloorActive())
    spdlog::warn("viewer: the thread stack floor is not in effect (thread_stack_floor.h)");
  lastStartMessage().clear();
  impl_->ctx = mg_start(&callbacks, impl_.get(), config);
  if (impl_->ctx == nullptr) {
    impl_->publisher.stop();
    releaseLibrary();
    const std::string why = lastStartMessage();
    throw ConfigError("--serve: cannot serve at " + ports + ": " +
                      (why.empty() ? std::string("address not on this machine, or port in use")
                                   : "civetweb: " + why));
  }
  mg_server_port bound[4]{};
  const int n = mg_get_server_ports(impl_->ctx, 4, bound);
  impl_->bound_port = n > 0 ? bound[0].port : options.port;
  spdlog::info("viewer: serving {} ({} files from {})", url(), impl_->files.size(),
               impl_->files.root());
}

ViewerServer::~ViewerServer() {
  impl_->publisher.stop();
  impl_->stopStreams(std::chrono::seconds(1));
  mg_stop(impl_->ctx);
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
  c.requests_refused = impl_->refused_requests.load();
  c.publisher = impl_->publisher.counters();
  return c;
}

}  // namespace ldsm::viewer
