#include "http_reply.h"

#include <civetweb.h>

namespace ldsm::viewer {

const char* reasonPhrase(int status) {
  switch (status) {
    case 200:
      return "OK";
    case 400:
      return "Bad Request";
    case 404:
      return "Not Found";
    case 405:
      return "Method Not Allowed";
    case 408:
      return "Request Timeout";
    case 411:
      return "Length Required";
    case 413:
      return "Content Too Large";
    case 431:
      return "Request Header Fields Too Large";
    case 503:
      return "Service Unavailable";
    case 505:
      return "HTTP Version Not Supported";
    default:
      return "Error";
  }
}

int writeResponse(mg_connection* conn, int status, const char* content_type,
                  const std::string& body, bool with_body) {
  mg_printf(conn,
            "HTTP/1.1 %d %s\r\nContent-Type: %s\r\nContent-Length: %zu\r\n"
            "Cache-Control: no-cache\r\nX-Content-Type-Options: nosniff\r\n"
            "Connection: close\r\n\r\n",
            status, reasonPhrase(status), content_type, body.size());
  if (with_body && !body.empty()) mg_write(conn, body.data(), body.size());
  return status;
}

bool writeStreamHead(mg_connection* conn) {
  return mg_printf(conn,
                   "HTTP/1.1 200 OK\r\nContent-Type: application/octet-stream\r\n"
                   "Transfer-Encoding: chunked\r\nCache-Control: no-store\r\n"
                   "X-Content-Type-Options: nosniff\r\nConnection: close\r\n\r\n") > 0;
}

}  // namespace ldsm::viewer
