// readPly: what writePly writes comes back (binary and ASCII), other tools' variants are read,
// and malformed files give errors naming the file.
#include <gtest/gtest.h>

#include <fstream>

#include "ldsm/drivers/ply_reader.h"
#include "ldsm/drivers/ply_writer.h"
#include "ldsm/error.h"
#include "test_paths.h"

namespace ldsm::drivers {
namespace {

void writeText(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

TEST(PlyReader, ReadsWhatTheWriterWrites) {
  const std::string dir = test::scratchDir("ply_reader_roundtrip");
  const std::vector<Eigen::Vector3f> pts = {{1.f, 2.f, 3.f}, {-4.5f, 0.25f, 1e3f}};
  const std::vector<std::array<std::uint8_t, 3>> colours = {{{10, 20, 30}}, {{255, 64, 0}}};
  for (PlyEncoding enc : {PlyEncoding::BinaryLittleEndian, PlyEncoding::Ascii}) {
    const std::string path = dir + "/p.ply";
    writePly(path, pts, colours, {0.5f, 7.f}, enc);
    const PlyPoints r = readPly(path);
    ASSERT_EQ(r.points.size(), 2u);
    EXPECT_EQ(r.points[1], pts[1]);
    ASSERT_EQ(r.colours.size(), 2u);
    EXPECT_EQ(r.colours[1], colours[1]);
    ASSERT_EQ(r.intensities.size(), 2u);
    EXPECT_FLOAT_EQ(r.intensities[0], 0.5f);
  }
}

TEST(PlyReader, SkipsOtherPropertiesAndReadsDoubles) {
  const std::string path = test::scratchDir("ply_reader_variants") + "/v.ply";
  writeText(path,
            "ply\nformat ascii 1.0\ncomment other tool\nelement vertex 1\nproperty double x\n"
            "property double y\nproperty double z\nproperty float nx\nproperty uchar red\n"
            "property uchar green\nproperty uchar blue\nelement face 0\n"
            "property list uchar int vertex_indices\nend_header\n1.5 2 3 0.1 9 8 7\n");
  const PlyPoints r = readPly(path);
  ASSERT_EQ(r.points.size(), 1u);
  EXPECT_FLOAT_EQ(r.points[0].x(), 1.5f);
  EXPECT_EQ(r.colours[0][2], 7);
  EXPECT_TRUE(r.intensities.empty());
}

TEST(PlyReader, MalformedFilesAreErrorsNamingTheFile) {
  const std::string dir = test::scratchDir("ply_reader_bad");
  auto expectError = [&](const std::string& text, const std::string& what) {
    const std::string path = dir + "/bad.ply";
    writeText(path, text);
    try {
      readPly(path);
      ADD_FAILURE() << "no error for " << what;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  expectError("not a ply\n", "not a PLY file");
  expectError("ply\nformat binary_big_endian 1.0\nelement vertex 1\nend_header\n",
              "unsupported format");
  expectError("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n1\n",
              "without x, y, z");
  expectError(
      "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000\nproperty float x\n"
      "property float y\nproperty float z\nend_header\nabc",
      "shorter than");
  expectError(
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
      "property float z\nend_header\n1 2 3\n4 5 x\n",
      "vertex 1 of 2");
  EXPECT_THROW(readPly(dir + "/missing.ply"), InputError);
}

}  // namespace
}  // namespace ldsm::drivers
