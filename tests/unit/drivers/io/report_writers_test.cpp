// JSON and PLY writers and the atomic file helper.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "ldsm/drivers/atomic_file.h"
#include "ldsm/drivers/json_writer.h"
#include "ldsm/drivers/ply_writer.h"
#include "ldsm/error.h"
#include "synthetic_trajectory.h"

namespace ldsm::drivers {
namespace {

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TEST(JsonWriter, NestedDocument) {
  JsonWriter w;
  w.beginObject();
  w.key("name").value("a \"q\"\n");
  w.key("n").value(std::int64_t{-3});
  w.key("x").value(0.1);
  w.key("bad").value(std::nan(""));
  w.key("list").beginArray().value(true).null().endArray();
  w.key("v").array({1.5, 2.0});
  w.key("empty").beginObject().endObject();
  w.endObject();
  EXPECT_EQ(w.str(),
            "{\n  \"name\": \"a \\\"q\\\"\\n\",\n  \"n\": -3,\n  \"x\": 0.1,\n  \"bad\": null,\n"
            "  \"list\": [\n    true,\n    null\n  ],\n  \"v\": [1.5, 2],\n  \"empty\": {}\n}\n");
}

TEST(JsonWriter, MisuseThrows) {
  JsonWriter a;
  a.beginObject();
  EXPECT_THROW(a.value(1.0), Error);  // no key
  EXPECT_THROW(a.str(), Error);       // still open
  JsonWriter b;
  EXPECT_THROW(b.endArray(), Error);
  JsonWriter c;
  EXPECT_THROW(c.key("k"), Error);
}

class PlyWriter : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = eval::testing::scratchDir("ply"); }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string dir_;
};

float floatAt(const std::string& s, std::size_t offset) {
  std::uint32_t bits = 0;
  for (int i = 0; i < 4; ++i) {
    bits |= static_cast<std::uint32_t>(static_cast<unsigned char>(s[offset + i])) << (8 * i);
  }
  float f = 0.0f;
  std::memcpy(&f, &bits, 4);
  return f;
}

TEST_F(PlyWriter, BinaryWithColoursAndIntensity) {
  const std::vector<Eigen::Vector3f> pts{{1.5f, -2.0f, 3.25f}, {0.1f, 0.2f, 0.3f}};
  const std::vector<std::array<std::uint8_t, 3>> rgb{{{255, 0, 10}}, {{1, 2, 3}}};
  const std::vector<float> intensity{0.5f, 7.0f};
  const std::string path = dir_ + "/c.ply";
  writePly(path, pts, rgb, intensity);
  const std::string s = slurp(path);
  const std::size_t body = s.find("end_header\n");
  ASSERT_NE(body, std::string::npos);
  const std::string header = s.substr(0, body);
  EXPECT_NE(header.find("format binary_little_endian 1.0"), std::string::npos);
  EXPECT_NE(header.find("element vertex 2"), std::string::npos);
  EXPECT_NE(header.find("property uchar red"), std::string::npos);
  EXPECT_NE(header.find("property float intensity"), std::string::npos);
  const std::size_t off = body + std::strlen("end_header\n");
  const std::size_t stride = 3 * 4 + 3 + 4;
  ASSERT_EQ(s.size(), off + 2 * stride);
  EXPECT_EQ(floatAt(s, off), 1.5f);
  EXPECT_EQ(floatAt(s, off + 4), -2.0f);
  EXPECT_EQ(floatAt(s, off + 8), 3.25f);
  EXPECT_EQ(static_cast<unsigned char>(s[off + 12]), 255);
  EXPECT_EQ(static_cast<unsigned char>(s[off + 14]), 10);
  EXPECT_EQ(floatAt(s, off + 15), 0.5f);
  EXPECT_EQ(floatAt(s, off + stride + 15), 7.0f);
}

TEST_F(PlyWriter, AsciiPointsOnly) {
  const std::string path = dir_ + "/a.ply";
  writePly(path, {{0.1f, 2.0f, -3.0f}}, {}, {}, PlyEncoding::Ascii);
  const std::string s = slurp(path);
  EXPECT_NE(s.find("format ascii 1.0"), std::string::npos);
  EXPECT_EQ(s.find("red"), std::string::npos);
  EXPECT_NE(s.find("end_header\n0.1 2 -3\n"), std::string::npos) << s;
}

TEST_F(PlyWriter, BadInputIsRejected) {
  const std::vector<Eigen::Vector3f> pts{{0, 0, 0}, {1, 1, 1}};
  EXPECT_THROW(writePly(dir_ + "/x.ply", pts, {{{1, 2, 3}}}), InputError);
  EXPECT_THROW(writePly(dir_ + "/x.ply", pts, {}, {1.0f}), InputError);
  const std::vector<Eigen::Vector3f> nan_pts{{0, std::nanf(""), 0}};
  EXPECT_THROW(writePly(dir_ + "/x.ply", nan_pts), InputError);
  EXPECT_FALSE(std::filesystem::exists(dir_ + "/x.ply"));
}

TEST_F(PlyWriter, AtomicWriteReplacesWholeFile) {
  const std::string path = dir_ + "/f.txt";
  writeFileAtomically(path, "first version, longer\n");
  writeFileAtomically(path, "second\n");
  EXPECT_EQ(slurp(path), "second\n");
  EXPECT_THROW(writeFileAtomically(dir_ + "/missing/f.txt", "x"), Error);
}

}  // namespace
}  // namespace ldsm::drivers
