// The viewer server's HTTP responses, written by ldsm rather than by civetweb (Debian's civetweb
// 1.15 crashed inside its own mg_send_http_error on a browser's favicon request): complete
// responses with a length, and the head of the chunked update stream. Every response closes its
// connection.
#pragma once

#include <string>

struct mg_connection;

namespace ldsm::viewer {

/// Writes a complete response (the body only when `with_body`); returns `status`.
int writeResponse(mg_connection* conn, int status, const char* content_type,
                  const std::string& body, bool with_body);

/// Writes the head of a 200 response whose body follows in chunks (mg_send_chunk); false when
/// the connection failed.
bool writeStreamHead(mg_connection* conn);

/// The reason phrase of the status codes the viewer sends ("Error" for others).
const char* reasonPhrase(int status);

}  // namespace ldsm::viewer
