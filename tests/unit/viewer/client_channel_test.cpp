// One page's channel: at most one batch in flight, written in order on the serving thread; a
// failed write ends it; stop() still lets the batch offered before it go out.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <thread>

#include "client_channel.h"

namespace ldsm::viewer {
namespace {

using namespace std::chrono_literals;

std::vector<WireMessage> batch(std::initializer_list<const char*> parts) {
  std::vector<WireMessage> b;
  for (const char* p : parts) b.push_back(WireMessage{p});
  return b;
}

TEST(ClientChannel, OneBatchInFlightWrittenInOrder) {
  ClientChannel channel;
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  std::vector<std::string> written;
  auto serving = std::async(std::launch::async, [&] {
    return channel.serve([&](const WireMessage& m) {
      released.wait();  // a slow page
      written.push_back(m.bytes);
      return true;
    });
  });
  ASSERT_TRUE(channel.offer(batch({"a", "bc"})));
  EXPECT_FALSE(channel.offer(batch({"skipped"}))) << "the first batch is still being written";
  release.set_value();
  const auto end = std::chrono::steady_clock::now() + 5s;
  while (channel.sentBytes() < 3 && std::chrono::steady_clock::now() < end)
    std::this_thread::sleep_for(1ms);
  ASSERT_TRUE(channel.offer(batch({"d"})));
  channel.stop();
  EXPECT_TRUE(serving.get()) << "ended by stop()";
  EXPECT_EQ(written, (std::vector<std::string>{"a", "bc", "d"})) << "the last batch still went";
  EXPECT_FALSE(channel.offer(batch({"late"})));
  EXPECT_FALSE(channel.failed());
}

TEST(ClientChannel, AFailedWriteEndsServing) {
  ClientChannel channel;
  std::atomic<int> calls{0};
  auto serving = std::async(std::launch::async, [&] {
    return channel.serve([&](const WireMessage&) { return ++calls == 1; });
  });
  ASSERT_TRUE(channel.offer(batch({"a", "b", "c"})));
  EXPECT_FALSE(serving.get());
  EXPECT_EQ(calls.load(), 2) << "nothing written after the failure";
  EXPECT_TRUE(channel.failed());
  EXPECT_FALSE(channel.offer(batch({"d"})));
}

TEST(ClientChannel, StopBeforeServingReturnsAtOnce) {
  ClientChannel channel;
  channel.stop();
  EXPECT_TRUE(channel.serve([](const WireMessage&) { return true; }));
}

}  // namespace
}  // namespace ldsm::viewer
