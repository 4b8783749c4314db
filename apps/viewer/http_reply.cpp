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

// The heads are built here and written with mg_write, not mg_printf: mg_printf formats into an
// 8 KiB stack buffer through vsnprintf, and civetweb's threads have small stacks (Debian's
// libcivetweb: 100 KiB), which an AddressSanitizer build overflowed answering a refused page.
int writeResponse(mg_connection* conn, int status, const char* content_type,
                  const std::string& body, bool with_body) {
  const std::string head = "HTTP/1.1 " + std::to_string(status) + " " + reasonPhrase(status) +
                           "\r\nContent-Type: " + content_type +
                           "\r\nContent-Length: " + std::to_string(body.size()) +
                           "\r\nCache-Control: no-cache\r\nX-Content-Type-Options: nosniff\r\n"
                           "Connection: close\r\n\r\n";
  mg_write(conn, head.data(), head.size());
  if (with_body && !body.empty()) mg_write(conn, body.data(), body.size());
  return status;
}

bool writeStreamHead(mg_connection* conn) {
  static constexpr char kHead[] =
      "HTTP/1.1 200 OK\r\nContent-Type: application/octet-stream\r\n"
      "Transfer-Encoding: chunked\r\nCache-Control: no-store\r\n"
      "X-Content-Type-Options: nosniff\r\nConnection: close\r\n\r\n";
  return mg_write(conn, kHead, sizeof(kHead) - 1) > 0;
}

}  // namespace ldsm::viewer
