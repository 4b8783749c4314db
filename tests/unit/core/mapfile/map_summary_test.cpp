#include <gtest/gtest.h>

#include "ldsm/error.h"
#include "ldsm/map_file.h"
#include "mapfile/map_codec.h"
#include "synthetic_map.h"

namespace ldsm {
namespace {

TEST(MapSummary, DescribesWhatTheFileHolds) {
  test::SyntheticMapSize size;
  size.keyframes = 12;
  size.data_every = 3;
  size.points_per_keyframe = 7;
  size.corners_per_keyframe = 5;
  size.vocabulary_bytes = 33;
  const MapData map = test::syntheticMap(size);
  const std::vector<std::uint8_t> bytes = encodeMap(map);
  const MapFileSummary s = summarizeMap(bytes.data(), bytes.size(), "m.ldsm");
  EXPECT_EQ(s.version, 1u);
  EXPECT_EQ(s.keyframes, 12u);
  EXPECT_EQ(s.data_keyframes, 4u);
  EXPECT_EQ(s.patch_points, 28u);
  EXPECT_EQ(s.corners, 20u);
  EXPECT_EQ(s.descriptors, 20u);
  EXPECT_EQ(s.points, 28u);
  EXPECT_EQ(s.graph_edges, map.graph.size());
  EXPECT_EQ(s.covisibility_edges, map.covisibility.size());
  EXPECT_EQ(s.vocabulary_bytes, 33u);
  EXPECT_EQ(s.camera.width, 752);
  EXPECT_EQ(s.camera.fx, 458.5);
  EXPECT_EQ(s.radial_k, -0.0125);
  EXPECT_TRUE(s.has_response);
  EXPECT_EQ(s.total_bytes, bytes.size());
  EXPECT_EQ(s.focal_scale, 1.0);
  EXPECT_EQ(s.cx_shift, 0.0);
  ASSERT_EQ(s.sections.size(), 8u);
  EXPECT_EQ(s.sections[2].tag, "KFDT");
  EXPECT_EQ(s.sections[7].tag, "CALR");
  std::uint64_t sum = 20 + 8 * 24;
  for (const MapFileSection& section : s.sections) sum += section.bytes;
  EXPECT_EQ(sum, bytes.size());
  // The keyframe centres lie on an ellipse of radii 4 and 1.5 (syntheticMap).
  EXPECT_NEAR(s.area_min[0], -4.0, 0.2);
  EXPECT_NEAR(s.area_max[0], 4.0, 1e-9);
  EXPECT_NEAR(s.area_max[1], 1.5, 0.2);
  EXPECT_NEAR(s.area_min[1], -1.5, 0.2);
  EXPECT_EQ(mapFileVocabulary(bytes.data(), bytes.size(), "m.ldsm"), map.vocabulary);
}

TEST(MapSummary, ErrorsAreTheLoaders) {
  std::vector<std::uint8_t> bytes = encodeMap(test::syntheticMap({}));
  bytes.resize(bytes.size() - 1);
  try {
    summarizeMap(bytes.data(), bytes.size(), "cut.ldsm");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("cut.ldsm: section CALR (calibration refinement): ", 0),
              0u)
        << e.what();
  }
}

}  // namespace
}  // namespace ldsm
