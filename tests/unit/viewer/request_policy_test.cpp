// What the viewer's server does with a request: files and the update stream for GET, nothing for
// upgrades (no WebSocket), bodies (closed unread) or other methods.
#include <gtest/gtest.h>

#include "request_policy.h"

namespace ldsm::viewer {
namespace {

RequestFacts request(const char* method, const char* path) {
  RequestFacts r;
  r.method = method;
  r.path = path;
  return r;
}

TEST(RequestPolicy, GetServesFilesAndTheStream) {
  EXPECT_EQ(judgeRequest(request("GET", "/")).route, Route::File);
  EXPECT_EQ(judgeRequest(request("HEAD", "/viewer.js")).route, Route::File);
  EXPECT_EQ(judgeRequest(request("GET", "/stream")).route, Route::Stream);
  const RequestVerdict head = judgeRequest(request("HEAD", "/stream"));
  EXPECT_EQ(head.route, Route::Refuse);
  EXPECT_EQ(head.status, 405);
  for (const char* method : {"POST", "PUT", "DELETE", "OPTIONS", "CONNECT", "PROPFIND", ""}) {
    const RequestVerdict v = judgeRequest(request(method, "/"));
    EXPECT_EQ(v.route, Route::Refuse) << method;
    EXPECT_EQ(v.status, 405) << method;
    EXPECT_FALSE(v.read_nothing_more) << method;
  }
}

TEST(RequestPolicy, UpgradesAreRefusedOnEveryPath) {
  for (const char* path : {"/stream", "/", "/ws", "/index.html"}) {
    RequestFacts r = request("GET", path);
    r.upgrade = true;
    const RequestVerdict v = judgeRequest(r);
    EXPECT_EQ(v.route, Route::Refuse) << path;
    EXPECT_EQ(v.status, 400) << path;
    EXPECT_NE(v.message.find("WebSocket"), std::string::npos) << v.message;
  }
}

TEST(RequestPolicy, BodiesAreRefusedUnread) {
  for (const char* method : {"GET", "POST"}) {
    RequestFacts r = request(method, "/stream");
    r.has_body = true;
    const RequestVerdict v = judgeRequest(r);
    EXPECT_EQ(v.route, Route::Refuse) << method;
    EXPECT_EQ(v.status, 400) << method;
    EXPECT_TRUE(v.read_nothing_more) << method;
  }
  EXPECT_FALSE(announcesBody(nullptr, nullptr));
  EXPECT_FALSE(announcesBody("0", nullptr));
  EXPECT_FALSE(announcesBody("000", nullptr));
  EXPECT_TRUE(announcesBody("1", nullptr));
  EXPECT_TRUE(announcesBody("1000000000000", nullptr));
  EXPECT_TRUE(announcesBody("", nullptr));
  EXPECT_TRUE(announcesBody(nullptr, "chunked"));
  EXPECT_TRUE(announcesBody("0", "identity"));
}

}  // namespace
}  // namespace ldsm::viewer
