// The viewer's prefix deltas: where arrays differ, what a page is sent, in chunks, and the layout
// of the stream's records (u32 length, then the message).
#include <gtest/gtest.h>

#include <cstring>
#include <limits>

#include "stream_delta.h"
#include "wire_format.h"

namespace ldsm::viewer {
namespace {

std::uint32_t u32(const std::string& b, std::size_t at) {
  std::uint32_t v;
  std::memcpy(&v, b.data() + at, 4);
  return v;
}

/// The message of a record, checked against the record's length prefix.
std::string message(const WireMessage& m) {
  EXPECT_GE(m.bytes.size(), kLengthBytes);
  EXPECT_EQ(u32(m.bytes, 0), m.bytes.size() - kLengthBytes);
  return m.bytes.substr(kLengthBytes);
}

std::vector<float> poses(int n, float offset = 0.f) {
  std::vector<float> v;
  for (int i = 0; i < n * kPoseStride; ++i) v.push_back(static_cast<float>(i) + offset);
  return v;
}

TEST(StreamDelta, FirstDifferenceIsPerElement) {
  const std::vector<float> a = poses(5);
  std::vector<float> b = a;
  EXPECT_EQ(firstDifference(a, b, kPoseStride), 5u);
  b[3 * kPoseStride + 6] += 1.f;  // last float of element 3
  EXPECT_EQ(firstDifference(a, b, kPoseStride), 3u);
  EXPECT_EQ(firstDifference(a, poses(2), kPoseStride), 2u);  // a prefix
  EXPECT_EQ(firstDifference({}, a, kPoseStride), 0u);
}

TEST(StreamDelta, PageStreamKeepsTheEarliestChange) {
  PageStream s;
  s.sent(10);
  s.changedFrom(7);
  s.changedFrom(9);  // a later change does not undo the earlier one
  EXPECT_EQ(s.valid, 7u);
  EXPECT_EQ(s.have, 10u);
  s.sent(12);
  EXPECT_EQ(s.valid, 12u);
}

TEST(WireFormat, DeltaSendsFromTheFirstChangeInChunks) {
  const std::vector<float> data = poses(10);
  std::vector<WireMessage> out;
  appendDelta(StreamKind::Trajectory, data, 4, 8, 4, out);  // page has 8, first 4 valid
  ASSERT_EQ(out.size(), 2u);                                // elements 4..7 and 8..9
  const std::string first = message(out[0]), second = message(out[1]);
  EXPECT_EQ(u32(first, 0), 1u);
  EXPECT_EQ(u32(first, 4), 4u);
  EXPECT_EQ(u32(first, 8), 4u);
  EXPECT_EQ(u32(first, 12), 8u);
  EXPECT_EQ(first.size(), kHeaderBytes + 4 * kPoseStride * sizeof(float));
  float value;
  std::memcpy(&value, first.data() + kHeaderBytes, 4);
  EXPECT_EQ(value, data[4 * kPoseStride]);
  EXPECT_EQ(u32(second, 4), 8u);
  EXPECT_EQ(u32(second, 12), 10u);
}

TEST(WireFormat, UpToDatePageGetsNothingAndShrinkingTruncates) {
  std::vector<WireMessage> out;
  appendDelta(StreamKind::Points, std::vector<float>(4 * 3), 3, 3, 100, out);
  EXPECT_TRUE(out.empty());
  appendDelta(StreamKind::Points, std::vector<float>(4 * 2), 2, 3, 100, out);
  ASSERT_EQ(out.size(), 1u);  // an empty message that only truncates to 2
  const std::string m = message(out[0]);
  EXPECT_EQ(m.size(), kHeaderBytes);
  EXPECT_EQ(u32(m, 8), 0u);
  EXPECT_EQ(u32(m, 12), 2u);
}

TEST(WireFormat, ImageMessageLayout) {
  ViewerImage img;
  img.frame_index = 3;
  img.width = 3;
  img.height = 2;
  img.pixels = {1, 2, 3, 4, 5, 6};
  img.points = {1.5f, 0.5f};
  const std::string m = message(encodeImage(img));
  EXPECT_EQ(u32(m, 0), kImageMessage);
  EXPECT_EQ(u32(m, 4), 3u);
  EXPECT_EQ(u32(m, 8), 2u);
  EXPECT_EQ(u32(m, 12), 1u);
  EXPECT_EQ(m[16 + 5], 6);
  ASSERT_EQ(m.size(), 16u + 8u + 8u);  // pixels padded to 8
  float x;
  std::memcpy(&x, m.data() + 24, 4);
  EXPECT_EQ(x, 1.5f);
}

TEST(WireFormat, FiguresAreJsonWithTheLists) {
  ViewerSnapshot s;
  s.figures.status = "tracking";
  s.figures.fps = std::numeric_limits<double>::quiet_NaN();  // never NaN on the wire
  s.loops = {{1, 2}, {3, 4}, {5, 6}};
  const std::string m = message(encodeFigures(s, 2));
  EXPECT_EQ(u32(m, 0), kFiguresMessage);
  const std::string json = m.substr(4);
  EXPECT_EQ(json.front(), '{');
  EXPECT_EQ(json.find_last_not_of('\n'), json.rfind('}'));
  EXPECT_NE(json.find("\"status\": \"tracking\""), std::string::npos) << json;
  EXPECT_EQ(json.find("nan"), std::string::npos) << json;
  EXPECT_EQ(json.find("[\n      1"), std::string::npos) << json;  // only the newest 2
  EXPECT_NE(json.find("\"current\": null"), std::string::npos) << json;
}

}  // namespace
}  // namespace ldsm::viewer
