#include "request_policy.h"

#include <cstring>

namespace ldsm::viewer {

RequestVerdict judgeRequest(const RequestFacts& r) {
  RequestVerdict v;
  if (r.has_body) {
    v.message = "the viewer accepts no request body\n";
    v.read_nothing_more = true;
    return v;
  }
  if (r.upgrade) {
    v.message = "no protocol upgrade here (the viewer has no WebSocket: GET /stream)\n";
    return v;
  }
  const bool get = r.method == "GET";
  if (!get && r.method != "HEAD") {
    v.status = 405;
    v.message = "only GET and HEAD\n";
    return v;
  }
  if (r.path == kStreamPath) {
    if (!get) {
      v.status = 405;
      v.message = "only GET\n";
      return v;
    }
    v.route = Route::Stream;
    return v;
  }
  v.route = Route::File;
  return v;
}

bool announcesBody(const char* content_length, const char* transfer_encoding) {
  if (transfer_encoding != nullptr) return true;
  if (content_length == nullptr) return false;
  const std::size_t n = std::strlen(content_length);
  return n == 0 || std::strspn(content_length, "0") != n;
}

}  // namespace ldsm::viewer
