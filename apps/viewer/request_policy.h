// What the viewer's server does with a request, decided from its method, path and headers alone
// (no civetweb here, so it is tested without sockets). The page only ever GETs files and the
// update stream, so anything else is refused: methods other than GET and HEAD, requests that
// announce a body (never read: the connection is closed instead) and protocol upgrades (the
// viewer has no WebSocket; nothing the client sends after its request is read).
#pragma once

#include <string>

namespace ldsm::viewer {

/// The path of the update stream (wire_format.h).
inline constexpr const char* kStreamPath = "/stream";

struct RequestFacts {
  std::string method;
  std::string path;       ///< without the query
  bool upgrade = false;   ///< has an Upgrade header (e.g. a WebSocket handshake)
  bool has_body = false;  ///< has Transfer-Encoding, or a Content-Length other than 0
};

enum class Route { File, Stream, Refuse };

struct RequestVerdict {
  Route route = Route::Refuse;
  int status = 400;     ///< for Refuse
  std::string message;  ///< for Refuse: the plain-text body
  /// Close without reading anything more from the client (the announced body stays unread).
  bool read_nothing_more = false;
};

RequestVerdict judgeRequest(const RequestFacts& request);

/// Whether these headers (null: absent) announce a body: any Transfer-Encoding, or a
/// Content-Length other than 0.
bool announcesBody(const char* content_length, const char* transfer_encoding);

}  // namespace ldsm::viewer
